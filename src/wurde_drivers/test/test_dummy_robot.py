"""The whole dummy robot under the MCP, and the dummy base driven through its real interfaces."""

from __future__ import annotations

import math
import os
import pathlib

import pytest
from sim_fixture import MAPS, Observer, median_interval, sim_config
from wurde_core.ros_adaptor import take_stamped
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.sim.kinematics import arc
from wurde_drivers.sim.mapfile import load_map

#: Every stream of the dummy Pluto (config/sim) and the interval its stamps must keep (s of
#: simulated time): base 10 Hz, sonar 10 Hz, power 1 Hz, truth every 20 ms step, laser one scan
#: per 190.625 ms (361 values at 38400 baud, Pluto 8.1), wrist 20 Hz, DMU 50 Hz, GPS 1 Hz (and
#: its Pluto 8.4 layout).
RATES = {
    'PlutoBaseTruth': ('Egomotion', 0.02), 'PlutoBaseMotion': ('Egomotion', 0.1),
    'PlutoBaseSonar': ('RangeFinder', 0.1), 'PlutoBaseBumpers': ('Bumper', 0.1),
    'PlutoBasePower': ('Power', 1.0), 'PlutoBaseCommand': ('ActuatorState', None),
    'PlutoLaser': ('RangeFinder', 0.190625), 'PlutoLaser/RWI': ('RangeFinder', 0.190625),
    'PlutoLaser/Timing': ('FVectorState', 0.190625), 'PlutoWrist': ('ActuatorState', 0.05),
    'PlutoDMU': ('DMUState', 0.02), 'PlutoDMU/Raw': ('DMUState', 0.02), 'PlutoGPS': ('GPS', 1.0),
    'PlutoGPS/Pluto': ('ActuatorState', 1.0),
}


def start_mcp(directory: pathlib.Path) -> ChildProcess:
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    mcp = ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(directory / 'mcp-config.xml'),
                        '-m', str(directory / 'mcp-mappings.xml'), '-a'], env=env)
    mcp.expect('MCP ready', timeout=60)
    return mcp


def test_the_dummy_robot_comes_up_under_the_mcp_and_every_stream_keeps_its_rate(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus
    sim_config(tmp_path)
    observer = Observer({stream: interface for stream, (interface, _) in RATES.items()})
    node = observer.manager.node
    standard = {'imu': (node.create_subscription(Imu, '/PlutoDMU/imu', lambda _: None, 10), Imu),
                'fix': (node.create_subscription(NavSatFix, '/PlutoGPS/fix', lambda _: None, 10), NavSatFix)}
    seen: dict[str, list] = {'imu': [], 'fix': []}

    def everything(o: Observer) -> bool:
        for key, (sub, kind) in standard.items():
            seen[key].extend(message for message, _ in take_stamped(sub))
        return all(seen.values()) and all(len(o.events[s]) >= 4 for s, (_, p) in RATES.items() if p)
    try:
        with start_mcp(tmp_path) as mcp:
            observer.until(everything, 'four events on every stream, an Imu and a NavSatFix', timeout=90)
            for stream, (_, period) in RATES.items():
                if period is not None:
                    assert median_interval(observer.stamps(stream)) == pytest.approx(period, abs=1e-5), stream
            # The laser at the start pose (3, 7.5, facing east; mounted 0.2 m ahead) in the office
            # corridor: the wall 1.2 m to its right, the north door open to the outer wall 7.5 m
            # to its left, the east wall 16.8 m ahead — the analytic distances.
            _, scan = observer.events['PlutoLaser'][0]
            assert len(scan.ranges) == 361 and len(observer.events['PlutoLaser/RWI'][0][1].ranges) == 181
            assert (scan.ranges[0], scan.ranges[180], scan.ranges[360]) == pytest.approx((1.2, 16.8, 7.5), abs=0.006)
            assert list(observer.events['PlutoLaser/Timing'][0][1].element) == [361]
            # Sonar: left and right, the corridor walls 0.9 m from the transducers on the 0.3 m
            # ring; ahead, the edges of the ±0.218 rad cone meet the corridor walls (1.2 m to each
            # side) at 1.2 / sin(0.218); behind, nothing within 8 m reads 8 (Pluto 5) but the cone
            # meets the west wall 3.3 m away.
            _, sonar = observer.events['PlutoBaseSonar'][0]
            assert (sonar.ranges[0], sonar.ranges[4], sonar.ranges[12]) == pytest.approx(
                (1.2 / math.sin(0.218), 0.9, 0.9), abs=1e-6)
            assert sonar.ranges[8] == pytest.approx(2.7, abs=1e-6)
            assert observer.infos['PlutoBaseSonar'].max_range == 8.0
            assert observer.infos['PlutoLaser'].max_range == pytest.approx(81.82)
            _, gps = observer.events['PlutoGPS'][0]
            assert (gps.satellites, gps.quality) == (8, 2)
            assert (gps.x, gps.y) == pytest.approx((3.0, 7.5), abs=1e-6)
            assert gps.latitude == pytest.approx(59.3498 + 7.5 / 111_000, abs=1e-5)
            # Pluto 8.4's layout of the same fix: force[0] satellites, force[3] quality.
            _, pluto = observer.events['PlutoGPS/Pluto'][0]
            assert (pluto.force[0], pluto.force[3]) == (8.0, 2.0)
            assert list(pluto.position) == pytest.approx([3.0, 7.5], abs=1e-5)
            _, dmu = observer.events['PlutoDMU/Raw'][0]
            assert dmu.accel_z == pytest.approx(9.80665)
            # The same, as standard ROS 2 messages: at rest facing east, a DGPS fix.
            imu, fix = seen['imu'][0], seen['fix'][0]
            assert imu.linear_acceleration.z == pytest.approx(9.80665) and imu.orientation.w == pytest.approx(1.0)
            assert fix.latitude == pytest.approx(gps.latitude) and fix.status.status == NavSatStatus.STATUS_SBAS_FIX
            mcp.stop(timeout=60)
            for module in ('PlutoBase', 'PlutoLaser', 'PlutoWrist', 'PlutoDMU', 'PlutoGPS'):
                assert f'MCP: {module} is alive' in mcp.stderr
                log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
                assert log.rstrip().endswith('--- exit code 0'), log[-2000:]   # all quit cleanly
    finally:
        observer.close()


@pytest.fixture
def base(ros_domain: int, tmp_path: pathlib.Path):  # type: ignore[no-untyped-def]
    """A dummy base alone, started facing north 0.85 m from the corridor's north wall."""
    path = sim_config(tmp_path, start='3 7.5 1.5707963267948966')
    with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path), '-n', 'PlutoBase']) as child:
        yield child   # the tests wait for its streams


def drive_observer() -> Observer:
    return Observer({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseDrive': 'RobotDrive',
                     'PlutoBaseBumpers': 'Bumper', 'PlutoBaseMotion': 'Egomotion'})


def test_driving_follows_closed_form_arcs_and_the_bumper_stops_the_base_at_a_wall(base: ChildProcess) -> None:
    observer = drive_observer()
    try:
        observer.until(lambda o: len(o.events['PlutoBaseTruth']) > 0, 'ground truth')
        steps_before = len(observer.events['PlutoBaseTruth'])
        # Turn on a circle of radius 0.5 m (0.25 m/s, 0.5 rad/s) for a while, commanding at ~10 Hz.
        deadline_events = steps_before + 150
        while len(observer.events['PlutoBaseTruth']) < deadline_events:
            observer.request('PlutoBaseDrive', trans_velocity=0.25, rot_velocity=0.5)
            observer.until(lambda o: len(o.events['PlutoBaseTruth']) > steps_before, 'truth', timeout=10)
            steps_before = len(observer.events['PlutoBaseTruth'])
            observer.manager.wait(0.1)
        truth = [m for _, m in observer.events['PlutoBaseTruth']]
        steady = [(a, b) for a, b in zip(truth, truth[1:])
                  if a.tv == b.tv == 0.25 and a.rv == b.rv == 0.5 and b.header.sequence == a.header.sequence + 1]
        assert len(steady) > 50
        for a, b in steady:
            dt = (b.header.stamp.sec - a.header.stamp.sec) + (b.header.stamp.nanosec - a.header.stamp.nanosec) * 1e-9
            expected = arc(a.location.x, a.location.y, a.location.theta, 0.25, 0.5, 0.02)
            assert dt == pytest.approx(0.02, abs=2e-6)   # stamps carry microseconds
            assert (b.location.x, b.location.y, b.location.theta) == pytest.approx(expected, abs=1e-9)
        # Now straight ahead: the robot heads roughly north to the corridor wall and bumps.
        observer.until(lambda o: True, 'pump')
        for _ in range(300):
            observer.request('PlutoBaseDrive', trans_velocity=0.0, rot_velocity=0.0)
            observer.manager.wait(0.05)
            observer.pump()
            if abs(observer.events['PlutoBaseTruth'][-1][1].tv) < 1e-9:
                break
        heading = observer.events['PlutoBaseTruth'][-1][1].location.theta
        turn = math.atan2(math.sin(math.pi / 2 - heading), math.cos(math.pi / 2 - heading))
        for _ in range(200):   # face north again
            observer.request('PlutoBaseDrive', trans_velocity=0.0, rot_velocity=max(-0.5, min(0.5, 2 * turn)))
            observer.manager.wait(0.05)
            observer.pump()
            heading = observer.events['PlutoBaseTruth'][-1][1].location.theta
            turn = math.atan2(math.sin(math.pi / 2 - heading), math.cos(math.pi / 2 - heading))
            if abs(turn) < 0.02:
                break
        bumped = lambda o: any(m.bumped for _, m in o.events['PlutoBaseBumpers'])  # noqa: E731
        for _ in range(400):
            observer.request('PlutoBaseDrive', trans_velocity=0.3, rot_velocity=0.0)
            observer.manager.wait(0.05)
            observer.pump()
            if bumped(observer):
                break
        assert bumped(observer), 'the front bumper never tripped'
        last = [m for _, m in observer.events['PlutoBaseBumpers'] if m.bumped][-1]
        assert list(last.bumpers) == [True, False]            # front, not back
        observer.until(lambda o: o.events['PlutoBaseTruth'][-1][1].tv == 0.0, 'the base stopped', timeout=10)
        final = observer.events['PlutoBaseTruth'][-1][1].location
        assert final.y == pytest.approx(8.7 - 0.35, abs=0.02)   # touching the wall at y = 8.7
        assert observer.infos['PlutoBaseDrive'].trans_velocity == 0.0
    finally:
        observer.close()


def test_a_command_that_stops_coming_stops_the_robot(base: ChildProcess) -> None:
    observer = drive_observer()
    try:
        observer.until(lambda o: 'PlutoBaseDrive' in o.infos and o.events['PlutoBaseTruth'], 'the base')
        observer.request('PlutoBaseDrive', rot_velocity=0.5)   # once, then silence
        observer.until(lambda o: any(m.rv != 0.0 for _, m in o.events['PlutoBaseTruth']), 'turning')
        observer.until(lambda o: o.events['PlutoBaseTruth'][-1][1].rv == 0.0 and
                       any(m.rv != 0.0 for _, m in o.events['PlutoBaseTruth']), 'stopped by the watchdog')
        moving = [stamp for stamp, m in observer.events['PlutoBaseTruth'] if m.rv != 0.0]
        # Commanded at the first moving step; stopped one command timeout (1 s) later, after the
        # deceleration (2 rad/s² from 0.5 rad/s: 0.25 s).
        assert moving[-1] - moving[0] == pytest.approx(1.0 + 0.25, abs=0.1)
        assert observer.infos['PlutoBaseDrive'].rot_velocity == 0.0
        observer.until(lambda o: 'no command for 1.00 s: stopping' in base.stderr, 'the warning', timeout=10)
    finally:
        observer.close()


@pytest.mark.parametrize('edit, reason', [
    ({'elements': {'base': {'type': 'Tank'}}}, 'type="Tank"'),
    ({'start': 'nowhere'}, 'start place "nowhere" is not in map'),
    ({'top': {'time-scale': 'fast'}}, 'time-scale="fast"'),
])
def test_a_bad_sim_config_is_refused_with_file_and_reason(ros_domain: int, tmp_path: pathlib.Path,
                                                          edit: dict, reason: str) -> None:
    path = sim_config(tmp_path, **edit)
    with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path)]) as child:
        assert child.process.wait(timeout=60) == 2
        child.stop()
    assert str(path) in child.stderr and reason in child.stderr


def test_a_bad_map_is_refused_by_the_dummy_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path) -> None:
    broken = tmp_path / 'broken.xml'
    broken.write_text((MAPS / 'office.xml').read_text().replace('<wall x1="5" y1="0"', '<wal x1="5" y1="0"'))
    path = sim_config(tmp_path / 'cfg', elements={'map': {'file': str(broken)}})
    with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path)]) as child:
        assert child.process.wait(timeout=60) == 2
        child.stop()
    line = next(i for i, text in enumerate(broken.read_text().splitlines(), 1) if '<wal ' in text)
    assert f'{broken}:{line}:' in child.stderr
    assert load_map(MAPS / 'office.xml').name == 'office'


def test_standard_ros_topics_scan_odometry_and_cmd_vel(base: ChildProcess, tmp_path: pathlib.Path) -> None:
    """ROS tools see a LaserScan and an Odometry, and a Twist on cmd_vel drives the base."""
    from geometry_msgs.msg import Twist
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import LaserScan
    observer = drive_observer()
    node = observer.manager.node
    scans = node.create_subscription(LaserScan, '/PlutoLaser/scan', lambda _: None, 10)
    odoms = node.create_subscription(Odometry, '/PlutoBase/odom', lambda _: None, 10)
    cmd_vel = node.create_publisher(Twist, '/PlutoBase/cmd_vel', 10)
    got: dict[str, list] = {'scan': [], 'odom': []}

    def take(o: Observer) -> bool:
        for key, sub, kind in (('scan', scans, LaserScan), ('odom', odoms, Odometry)):
            got[key].extend(message for message, _ in take_stamped(sub))
        return bool(got['scan']) and bool(got['odom'])

    with ChildProcess([find_executable('wurde_drivers', 'dummy_sick'), '-c', str(tmp_path / 'sim-config.xml'),
                       '-n', 'PlutoLaser']):
        try:
            observer.until(take, 'a LaserScan and an Odometry')
            scan = got['scan'][0]
            assert len(scan.ranges) == 361 and scan.angle_min == pytest.approx(-math.pi / 2)
            assert scan.range_max == pytest.approx(81.82) and scan.header.frame_id == 'PlutoLaser'
            # Facing north from (3, 7.5): straight ahead the laser (0.2 m forward) sees the wall
            # at y = 8.7 through no door (x = 3 is west of the door at 3.05..3.95).
            assert scan.ranges[180] == pytest.approx(1.0, abs=0.006)
            assert got['odom'][0].child_frame_id == 'base_link'
            twist = Twist()
            twist.angular.z = 0.4

            def turning(o: Observer) -> bool:
                cmd_vel.publish(twist)
                return any(m.rv == pytest.approx(0.4) for _, m in o.events['PlutoBaseTruth'])
            observer.until(turning, 'the base turning on cmd_vel', timeout=30)
        finally:
            observer.close()


def test_the_dummy_lasers_pose_between_two_truth_samples_turns_the_short_way() -> None:
    """A scan's pose comes from the truth interpolated at its centre time; a robot turning past
    west between two samples (+3.12 → -3.12 rad) faces west, not east (a test_slam_module run on a
    loaded machine, whose half turn went past 180 degrees, got a scan taken facing east)."""
    from wurde_drivers.sim.dummies.sick import TruthHistory
    history = TruthHistory()
    history.add(10.0, 1.0, 2.0, 3.12)
    history.add(10.1, 1.1, 2.0, -3.12)
    x, y, theta = history.at(10.05)
    assert (x, y) == pytest.approx((1.05, 2.0))
    assert abs(theta) == pytest.approx(math.pi, abs=1e-9)
    assert history.at(10.025)[2] == pytest.approx(3.12 + 0.25 * (2 * math.pi - 6.24))
    history.add(10.2, 1.2, 2.0, -3.0)
    assert history.at(10.15)[2] == pytest.approx(-3.06)
