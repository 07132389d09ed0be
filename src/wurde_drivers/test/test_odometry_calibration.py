"""The base's odometry calibration (wurde_drivers.streams.calibration): scales 1, 1 pass the raw
odometry through unchanged; other scales scale each increment of distance and of heading, on top of
a simulated odometry that counts too much distance and too little rotation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wurde_drivers.sim.robot import OdometryNoise, RobotSpec, SimRobot
from wurde_drivers.sim.world import World
from wurde_drivers.streams.calibration import OdometryCalibration


def test_identity_passes_raw_odometry_through() -> None:
    c = OdometryCalibration()
    assert c.apply(1.0, 2.0, 0.3, 0.5, 0.1) == (1.0, 2.0, 0.3, 0.5, 0.1)
    assert c.problem(1.0, 1.0) == ''
    assert 'distance scale 3.0 is not in' in c.problem(3.0, 1.0)
    assert 'rotation scale nan' in c.problem(1.0, math.nan)


def test_scales_correct_a_drive_and_a_turn() -> None:
    c = OdometryCalibration()
    c.apply(0.0, 0.0, 0.0, 0.0, 0.0)
    c.set(1 / 1.03, 1 / 0.97)
    raw = [(0.0, 0.0, 0.0)]
    # The raw odometry: 1.03 m straight ahead in 100 steps, then 0.97 rad to the left.
    for k in range(1, 101):
        raw.append((1.03 * k / 100, 0.0, 0.0))
    for k in range(1, 101):
        raw.append((1.03, 0.0, 0.97 * k / 100))
    out = [c.apply(x, y, t, 0.3, 0.0) for x, y, t in raw]
    x, y, theta, tv, _ = out[-1]
    assert (x, y, theta) == pytest.approx((1.0, 0.0, 1.0), abs=1e-9)
    assert tv == pytest.approx(0.3 / 1.03)


def test_the_simulated_odometry_takes_a_calibration_error() -> None:
    noise = OdometryNoise(scale=1.03, turn_scale=0.97)
    assert not noise.is_zero
    robot = SimRobot(World(), RobotSpec(odometry_noise=noise), np.random.default_rng(1))
    robot.command(0.5, 0.0)
    while robot.truth.x < 1.0:
        robot.step(0.02)
    robot.command(0.0, 0.5)
    while robot.truth.theta < 1.0:
        robot.step(0.02)
    robot.command(0.0, 0.0)
    for _ in range(100):
        robot.step(0.02)
    # (the turn begins while the robot still rolls: the path bends, hence 1e-4, not exact)
    assert math.hypot(robot.odometry.x, robot.odometry.y) == pytest.approx(
        1.03 * math.hypot(robot.truth.x, robot.truth.y), rel=1e-4)
    assert robot.odometry.theta == pytest.approx(0.97 * robot.truth.theta, rel=1e-4)
