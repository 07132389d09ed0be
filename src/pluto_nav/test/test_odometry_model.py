"""The odometry increment covariance: its form, and that it fits the simulated base's errors."""

import math

import numpy as np
import pytest
from wurde_drivers.sim.robot import OdometryNoise, RobotSpec, SimRobot
from wurde_drivers.sim.world import World

from pluto_nav.geometry import compose, relative, wrap
from pluto_nav.odometry_model import OdometryNoiseModel, increment_covariance, laser_increment

MODEL = OdometryNoiseModel(trans=0.05, rot=0.05, drift=0.02)


def test_standing_still_gives_the_floor():
    cov = increment_covariance((0, 0, 0), MODEL)
    assert np.allclose(cov, np.diag([MODEL.floor_xy ** 2] * 2 + [MODEL.floor_theta ** 2]))


def test_a_straight_metre():
    cov = increment_covariance((1.0, 0.0, 0.0), MODEL)
    floor = MODEL.floor_xy ** 2
    assert cov[0, 0] == pytest.approx(0.05 ** 2 + floor)            # trans² per metre
    assert cov[2, 2] == pytest.approx(0.02 ** 2 + MODEL.floor_theta ** 2)   # drift
    assert cov[1, 1] == pytest.approx(0.25 * cov[2, 2] - 0.25 * MODEL.floor_theta ** 2 + floor)
    assert np.allclose(cov, cov.T)
    backwards = increment_covariance((-1.0, 0.0, 0.0), MODEL)
    assert np.allclose(np.diag(backwards), np.diag(cov))


def test_turning_on_the_spot():
    cov = increment_covariance((0.0, 0.0, -2.0), MODEL)
    assert cov[2, 2] == pytest.approx(0.05 ** 2 * 2.0 + MODEL.floor_theta ** 2)
    assert cov[0, 0] == pytest.approx(MODEL.floor_xy ** 2)


@pytest.mark.parametrize('tv, rv', [(0.5, 0.0), (0.0, 1.0), (0.4, 0.6), (-0.3, 0.2)])
def test_the_model_fits_the_simulated_base(tv, rv):
    """The simulated base's increment errors over 0.2 s, normalised by the model, have about
    unit variance in the directions that move (``OdometryNoise`` is the same model)."""
    world = World([(-500, -500, 500, -500), (500, -500, 500, 500), (500, 500, -500, 500),
                   (-500, 500, -500, -500)])
    noise = OdometryNoise(MODEL.trans, MODEL.rot, MODEL.drift)
    robot = SimRobot(world, RobotSpec(odometry_noise=noise), np.random.default_rng(4))
    robot.command(tv, rv)
    for _ in range(40):
        robot.step(0.05)
    errors = []
    for _ in range(600):
        t0, o0 = _pose(robot.truth), _pose(robot.odometry)
        for _ in range(4):
            robot.step(0.05)
        u_true, u_odo = relative(t0, _pose(robot.truth)), relative(o0, _pose(robot.odometry))
        e = u_odo - u_true
        e[2] = wrap(e[2])
        errors.append(e / np.sqrt(np.diag(increment_covariance(u_odo, MODEL))))
    spread = np.std(errors, axis=0)
    moving = [0, 2] if tv and rv else ([0] if tv else [2])
    assert np.all((spread[moving] > 0.8) & (spread[moving] < 1.25)), spread
    assert np.all(spread < 1.25), spread


def _pose(state):
    return (state.x, state.y, state.theta)


def test_laser_increment_moves_the_increment_to_the_mount():
    mount = (0.2, 0.05, 0.1)
    u = np.array([0.3, 0.02, 0.4])
    cov = increment_covariance(u, MODEL)
    sensor_u, sensor_cov = laser_increment(u, cov, mount)
    # The sensor's increment is what the two sensor poses say.
    robot0, robot1 = np.array([1.0, 2.0, 0.3]), compose((1.0, 2.0, 0.3), u)
    expected = relative(compose(robot0, mount), compose(robot1, mount))
    assert np.allclose(sensor_u, expected)
    # The covariance goes through the map's Jacobian (numeric here).
    jac = np.column_stack([(laser_increment(u + d, cov, mount)[0]
                            - laser_increment(u - d, cov, mount)[0]) / 2e-6
                           for d in np.eye(3) * 1e-6])
    assert np.allclose(sensor_cov, jac @ cov @ jac.T, rtol=1e-6, atol=1e-12)
    same, same_cov = laser_increment(u, cov, (0, 0, 0))
    assert np.allclose(same, u) and np.allclose(same_cov, cov)


@pytest.mark.parametrize('field', ['trans', 'rot', 'drift', 'floor_xy', 'floor_theta'])
def test_negative_or_infinite_parameters_are_refused(field):
    for value in (-0.1, math.inf):
        with pytest.raises(ValueError, match=field):
            OdometryNoiseModel(**{field: value})
