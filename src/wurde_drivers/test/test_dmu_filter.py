"""Pluto's DMUstate filter: heading integration, low-pass step response, reported delay."""

from __future__ import annotations

import math

import pytest

from wurde_drivers.dmu.device import RawSample
from wurde_drivers.dmu.filter import DmuFilter


def sample(*, rate_z: float = 0.0, accel_x: float = 0.0, roll: float | None = 0.0,
           pitch: float | None = 0.0) -> RawSample:
    return RawSample(stamp=0.0, roll=roll, pitch=pitch, rate_x=0.0, rate_y=0.0, rate_z=rate_z,
                     accel_x=accel_x, accel_y=0.0, accel_z=9.81, temperature=25.0, time_ticks=0)


def test_heading_of_a_constant_rate_is_rate_times_time() -> None:
    f = DmuFilter(cutoff_hz=2.0)
    rate, dt = 0.3, 0.01
    for k in range(1001):
        state = f.update(sample(rate_z=rate), 5.0 + k * dt)
    assert state.theta == pytest.approx(rate * 10.0, rel=1e-9)
    assert state.rate_z == pytest.approx(rate)


def test_heading_is_not_wrapped() -> None:
    f = DmuFilter(cutoff_hz=5.0)
    for k in range(2001):
        state = f.update(sample(rate_z=2.0), k * 0.01)
    assert state.theta == pytest.approx(40.0) and state.theta > 2 * math.pi


@pytest.mark.parametrize('cutoff_hz, dt', [(1.0, 0.01), (4.0, 0.002), (0.5, 0.03)])
def test_step_response_reaches_63_percent_after_one_time_constant(cutoff_hz: float,
                                                                  dt: float) -> None:
    f = DmuFilter(cutoff_hz)
    tau = 1 / (2 * math.pi * cutoff_hz)
    f.update(sample(accel_x=0.0), 0.0)
    k = 0
    while True:
        k += 1
        state = f.update(sample(accel_x=1.0), k * dt)
        if state.accel_x >= 1 - math.exp(-1):
            break
        assert k * dt < 2 * tau, 'never reached 63 %'
    assert k * dt == pytest.approx(tau, abs=dt)


def test_delay_is_reported_and_subtracted_from_the_stamp() -> None:
    f = DmuFilter(cutoff_hz=2.0)
    assert f.filter_delay == pytest.approx(1 / (2 * math.pi * 2.0))
    state = f.update(sample(), 100.0)
    assert state.stamp == pytest.approx(100.0 - f.filter_delay)


def test_pitch_and_roll_pass_through_and_may_be_absent() -> None:
    f = DmuFilter(cutoff_hz=1.0)
    state = f.update(sample(roll=0.1, pitch=-0.2), 0.0)
    assert (state.psi, state.phi) == (0.1, -0.2)
    state = f.update(sample(roll=None, pitch=None), 0.1)
    assert state.psi is None and state.phi is None


def test_stamps_that_do_not_advance_change_nothing_and_reset_restarts() -> None:
    f = DmuFilter(cutoff_hz=1.0)
    f.update(sample(rate_z=1.0), 1.0)
    f.update(sample(rate_z=1.0), 2.0)
    before = f.update(sample(rate_z=50.0), 2.0)
    assert before.theta == pytest.approx(1.0) and before.rate_z == pytest.approx(1.0)
    f.reset()
    assert f.update(sample(rate_z=3.0), 9.0).theta == 0.0


@pytest.mark.parametrize('bad', [0.0, -1.0, math.nan, math.inf])
def test_cutoff_must_be_positive(bad: float) -> None:
    with pytest.raises(ValueError):
        DmuFilter(bad)
