"""The simulated robot against analytic geometry: sensors, bumpers, odometry, repeatability."""

import math

import numpy as np
import pytest

from wurde_drivers.sim.body import SonarRing
from wurde_drivers.sim.clock import make_rng
from wurde_drivers.sim.inertial import GRAVITY, DmuModel, GpsModel
from wurde_drivers.sim.kinematics import DriveLimits
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.robot import OdometryNoise, RobotSpec, SimRobot
from wurde_drivers.sim.world import World

#: A 10 m × 6 m room with its corner at the origin.
ROOM = World([(0, 0, 10, 0), (10, 0, 10, 6), (10, 6, 0, 6), (0, 6, 0, 0)], name='room')
FAST = DriveLimits(max_tv=1.0, max_rv=2.0, tv_accel=0.0, rv_accel=0.0)


def run(robot: SimRobot, seconds: float, dt: float = 0.02) -> None:
    for _ in range(round(seconds / dt)):
        robot.step(dt)


def test_laser_ranges_equal_the_distances_to_the_walls() -> None:
    model = LaserModel(LaserGeometry(count=181, units='cm'), make_rng(1))
    ranges = model.scan(ROOM, 4.0, 3.0, 0.0)
    angles = np.radians(np.arange(-90, 91))
    # Right (−90°) the wall y=0 at 3 m, ahead the wall x=10 at 6 m, left y=6 at 3 m.
    assert ranges[0] == pytest.approx(3.0) and ranges[90] == pytest.approx(6.0)
    assert ranges[180] == pytest.approx(3.0)
    expected = np.minimum(np.where(np.sin(angles) > 1e-12, 3.0 / np.maximum(np.sin(angles), 1e-12), np.inf),
                          np.where(np.sin(angles) < -1e-12, 3.0 / np.maximum(-np.sin(angles), 1e-12), np.inf))
    expected = np.minimum(expected, np.where(np.cos(angles) > 1e-12, 6.0 / np.maximum(np.cos(angles), 1e-12), np.inf))
    assert np.all(np.abs(ranges - expected) <= 0.005 + 1e-9)   # quantised to 1 cm


def test_laser_units_maximum_range_and_inverted_order() -> None:
    hall = World([(100, -50, 100, 50)])
    cm = LaserModel(LaserGeometry(count=361, units='cm'), make_rng(1)).scan(hall, 0.0, 0.0, 0.0)
    mm = LaserModel(LaserGeometry(count=361, units='mm'), make_rng(1)).scan(hall, 99.0, 0.0, 0.0)
    assert math.isinf(cm[180])        # 100 m is past the LMS's 81.82 m: the "value > maximum" reading
    assert mm[180] == pytest.approx(1.0) and math.isinf(mm[0])   # mm mode reads to 8.182 m only
    geometry = LaserGeometry(count=181, inverted=True)
    inverted = LaserModel(geometry, make_rng(1)).scan(ROOM, 4.0, 1.0, 0.0)
    assert inverted[0] == pytest.approx(5.0) and inverted[180] == pytest.approx(1.0)


def test_laser_timing_follows_the_baud_rate_as_pluto_says() -> None:
    slow = LaserGeometry(count=361, baudrate=38400)
    fast = LaserGeometry(count=361, baudrate=500000)
    assert slow.telegram_bytes == 732 and slow.scan_period_s == pytest.approx(0.190625)  # "about 200 ms"
    assert fast.scan_period_s == pytest.approx(2 / 75)   # the mirror limits: 37.5 scans/s
    assert LaserGeometry(count=181, baudrate=500000).scan_period_s == pytest.approx(1 / 75)


def test_sonar_reads_the_wall_distance_or_eight_metres() -> None:
    sonar = SonarRing(count=4, radius=0.0, half_angle=0.0)
    ranges = sonar.ranges(ROOM, 2.0, 3.0, 0.0)
    assert list(ranges) == pytest.approx([8.0, 3.0, 2.0, 3.0])   # ahead 8 m is past 8 m → 8 (Pluto 5)
    cone = SonarRing(count=1, radius=0.0, half_angle=math.radians(30)).ranges(ROOM, 5.0, 5.0, math.pi / 2)
    assert cone[0] == pytest.approx(1.0)


def test_bumper_trips_at_a_wall_and_the_base_stops() -> None:
    robot = SimRobot(ROOM, RobotSpec(limits=FAST), make_rng(1), start=(5.0, 3.0, 0.0))
    robot.command(1.0, 0.0)
    run(robot, 6.0)
    assert robot.bumper_stop and robot.bumpers == (True, False)
    assert robot.truth.x == pytest.approx(10.0 - robot.spec.bumpers.radius, abs=1e-6)
    assert robot.truth.tv == 0.0 and robot.tv_command == 0.0
    x = robot.truth.x
    run(robot, 1.0)
    assert robot.truth.x == x                       # stays stopped
    robot.command(-0.5, 0.0)                        # backing away is allowed
    run(robot, 1.0)
    assert robot.truth.x == pytest.approx(x - 0.5, abs=1e-6) and robot.bumpers == (False, False)


def test_back_bumper_when_reversing_into_a_wall() -> None:
    robot = SimRobot(ROOM, RobotSpec(limits=FAST), make_rng(1), start=(1.0, 3.0, 0.0))
    robot.command(-0.5, 0.0)
    run(robot, 3.0)
    assert robot.bumpers == (False, True) and robot.bumper_stop


def test_odometry_is_exact_without_noise_and_starts_at_zero() -> None:
    robot = SimRobot(ROOM, RobotSpec(limits=FAST), make_rng(1), start=(2.0, 2.0, math.pi / 2))
    robot.command(0.2, 0.1)
    run(robot, 5.0)
    odo, truth = robot.odometry, robot.truth
    radius = 0.2 / 0.1
    assert (odo.x, odo.y, odo.theta) == pytest.approx((radius * math.sin(0.5), radius * (1 - math.cos(0.5)), 0.5))
    assert (truth.x, truth.y) == pytest.approx((2.0 - radius * (1 - math.cos(0.5)), 2.0 + radius * math.sin(0.5)))


def trace(seed: int, noise: OdometryNoise) -> list[tuple[float, ...]]:
    robot = SimRobot(ROOM, RobotSpec(limits=FAST, odometry_noise=noise), make_rng(seed, 'base'),
                     start=(2.0, 3.0, 0.0))
    laser = LaserModel(LaserGeometry(count=181, noise_sigma=0.02), make_rng(seed, 'laser'))
    out = []
    for i in range(200):
        robot.command(0.5, 0.3 * math.sin(i / 20))
        robot.step(0.05)
        o = robot.odometry
        out.append((o.x, o.y, o.theta, *laser.scan(ROOM, robot.truth.x, robot.truth.y, robot.truth.theta)[:5]))
    return out


def test_the_same_seed_repeats_a_run_exactly_and_another_does_not() -> None:
    noise = OdometryNoise(trans=0.05, rot=0.05, drift=0.01)
    assert trace(3, noise) == trace(3, noise)
    assert trace(3, noise) != trace(4, noise)


def test_odometry_noise_and_drift_make_odometry_leave_the_truth() -> None:
    robot = SimRobot(ROOM, RobotSpec(limits=FAST, odometry_noise=OdometryNoise(drift=0.05)), make_rng(1),
                     start=(1.0, 3.0, 0.0))
    robot.command(0.5, 0.0)
    run(robot, 10.0)
    assert robot.truth.theta == 0.0
    assert robot.odometry.theta == pytest.approx(0.05 * 5.0, rel=1e-6)   # 5 m driven


def test_dmu_heading_integrates_the_rate_and_gps_converts_the_position() -> None:
    dmu = DmuModel(make_rng(1), rate_bias=0.01)
    for _ in range(100):
        reading = dmu.step(0.5, 0.2, 0.0, 0.1)
    assert reading.theta == pytest.approx((0.2 + 0.01) * 10.0)
    assert (reading.accel_y, reading.accel_z) == pytest.approx((0.1, GRAVITY))
    gps = GpsModel(make_rng(1), lambda x, y: (y / 111000.0, x / 111000.0), satellites=7, quality=2)
    fix = gps.fix(111.0, 222.0)
    assert (fix.latitude, fix.longitude, fix.satellites) == pytest.approx((0.002, 0.001, 7))


def test_a_start_inside_a_wall_is_refused() -> None:
    with pytest.raises(ValueError, match='closer than the robot radius'):
        SimRobot(ROOM, RobotSpec(), make_rng(1), start=(0.1, 3.0, 0.0))
