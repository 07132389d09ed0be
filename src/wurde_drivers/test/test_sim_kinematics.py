"""The simulated base integrates commanded velocities along closed-form arcs."""

import math

import pytest

from wurde_drivers.sim.axis import Axis
from wurde_drivers.sim.clock import SimClock, make_rng
from wurde_drivers.sim.kinematics import BaseState, DriveLimits, arc, ramp, step_base

NO_RAMP = DriveLimits(max_tv=2.0, max_rv=2.0, tv_accel=0.0, rv_accel=0.0)


def drive(tv: float, rv: float, seconds: float, dt: float, limits: DriveLimits = NO_RAMP,
          start: BaseState = BaseState()) -> BaseState:
    state = start
    for _ in range(round(seconds / dt)):
        state = step_base(state, tv, rv, limits, dt)
    return state


def test_straight_line_is_v_times_t_along_the_heading() -> None:
    end = drive(0.5, 0.0, 4.0, 0.02, start=BaseState(1.0, 2.0, math.pi / 6))
    assert end.x == pytest.approx(1.0 + 2.0 * math.cos(math.pi / 6), abs=1e-9)
    assert end.y == pytest.approx(2.0 + 2.0 * math.sin(math.pi / 6), abs=1e-9)
    assert end.theta == pytest.approx(math.pi / 6)


@pytest.mark.parametrize('dt', [0.001, 0.02, 0.1])
def test_constant_v_and_w_follow_the_circle_whatever_the_step(dt: float) -> None:
    v, w, t = 0.4, 0.5, 3.0
    end = drive(v, w, t, dt)
    radius = v / w
    assert end.x == pytest.approx(radius * math.sin(w * t), abs=1e-9)
    assert end.y == pytest.approx(radius * (1 - math.cos(w * t)), abs=1e-9)
    assert end.theta == pytest.approx(w * t, abs=1e-12)


def test_a_full_circle_comes_back_to_the_start_with_theta_unwrapped() -> None:
    w = 2 * math.pi / 12.5
    end = drive(0.3, w, 12.5, 0.01)
    assert (end.x, end.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert end.theta == pytest.approx(2 * math.pi)


def test_turning_on_the_spot_does_not_move_the_centre() -> None:
    end = drive(0.0, -1.0, 1.5, 0.02)
    assert (end.x, end.y, end.theta) == pytest.approx((0.0, 0.0, -1.5))


def test_velocity_and_acceleration_limits_are_respected() -> None:
    limits = DriveLimits(max_tv=1.0, max_rv=1.0, tv_accel=0.5, rv_accel=1.0)
    state = step_base(BaseState(), 5.0, -5.0, limits, 0.1)
    assert (state.tv, state.rv) == pytest.approx((0.05, -0.1))
    assert state.acceleration == pytest.approx(0.5)
    state = drive(5.0, -5.0, 10.0, 0.1, limits)
    assert (state.tv, state.rv) == (1.0, -1.0)
    # Distance while ramping up to 1 m/s at 0.5 m/s² (2 s), then 8 s at full speed,
    # along an arc whose exact form is checked above: here only the speed matters.
    assert ramp(0.0, 1.0, 0.5, 0.5) == 0.25 and ramp(1.0, -1.0, 0.0, 0.1) == -1.0


def test_arc_matches_its_straight_limit() -> None:
    curved = arc(0.0, 0.0, 0.3, 1.0, 1e-7, 2.0)
    straight = arc(0.0, 0.0, 0.3, 1.0, 0.0, 2.0)
    assert curved == pytest.approx(straight, abs=1e-6)


def test_clock_runs_fixed_steps_and_seeded_sources_repeat() -> None:
    clock = SimClock(step_s=0.02, time_scale=10.0, start=100.0)
    for _ in range(50):
        clock.tick()
    assert clock.elapsed == pytest.approx(1.0) and clock.now == pytest.approx(101.0)
    assert clock.wall_period_s == pytest.approx(0.002)
    assert list(make_rng(7, 'a').normal(size=3)) == list(make_rng(7, 'a').normal(size=3))
    assert list(make_rng(7, 'a').normal(size=3)) != list(make_rng(7, 'b').normal(size=3))
    with pytest.raises(ValueError):
        SimClock(step_s=0.0)


def test_wrist_axis_reaches_its_target_within_its_limits() -> None:
    axis = Axis(-1.0, 1.0, max_velocity=1.0, max_acceleration=2.0)
    assert not axis.command(0.5, 0.0, 1.0)   # Pluto 8.3: velocity and acceleration must be > 0
    assert axis.command(0.8, 0.5, 1.0)
    peak, before = 0.0, 0.0
    for _ in range(400):
        axis.step(0.01)
        peak = max(peak, abs(axis.velocity))
        assert abs(axis.velocity - before) <= 1.0 * 0.01 + 1e-9   # never more than accel × dt
        before = axis.velocity
    assert axis.position == pytest.approx(0.8) and axis.velocity == 0.0 and not axis.moving
    assert peak == pytest.approx(0.5)
    assert axis.command(5.0, 1.0, 2.0) and axis.target == 1.0   # clamped to the joint limit


def test_pluto_angles_become_the_standard_quaternion() -> None:
    from wurde_drivers.ros_std import quaternion
    assert quaternion(math.pi / 2, 0.0, 0.0) == pytest.approx((0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)))
    assert quaternion(0.0, 0.0, math.pi) == pytest.approx((1.0, 0.0, 0.0, 0.0), abs=1e-12)   # roll about x
    x, y, z, w = quaternion(0.3, -0.2, 0.1)
    assert x * x + y * y + z * z + w * w == pytest.approx(1.0)
