"""Every device on a standard ROS 2 topic (issue 17), seen from rclpy as a ROS tool sees it.

The shipped executables run as real processes; the test subscribes to their standard topics and
to the WURDE streams they mirror, and checks type, frames, values against the stream's, the
covariances, and ``/tf_static`` against the config's mounting numbers.
"""

from __future__ import annotations

import math
import pathlib
from collections.abc import Iterator
from contextlib import ExitStack
from typing import Any

import pytest
from sim_fixture import Observer, heartbeat, sim_config
from wurde_core.ros_adaptor import take_stamped
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.ptu.emulator import Ptu46Emulator
from wurde_drivers.ros_std_covariance import MIN_VARIANCE, fix_covariance, lowpass_variance_factor
from wurde_drivers.sim.config import load_sim_config

#: The simulator's noise for this test: odometry 5 % per sqrt(m), DMU rate noise 0.01 rad/s.
TRANS_NOISE = 0.05
RATE_NOISE = 0.01


class Topics:
    """rclpy subscriptions on the observer's node; :meth:`take` keeps every message per topic."""

    def __init__(self, node: Any, topics: dict[str, type]) -> None:
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from tf2_msgs.msg import TFMessage
        static = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.subscriptions = {name: node.create_subscription(kind, name, lambda _: None, 100)
                              for name, kind in topics.items()}
        self.subscriptions['/tf_static'] = node.create_subscription(TFMessage, '/tf_static', lambda _: None,
                                                                    static)
        self.messages: dict[str, list[Any]] = {name: [] for name in self.subscriptions}
        self.frames: dict[str, Any] = {}

    def take(self) -> None:
        for name, sub in self.subscriptions.items():
            self.messages[name].extend(message for message, _ in take_stamped(sub))
        for message in self.messages['/tf_static']:
            for t in message.transforms:
                self.frames[t.child_frame_id] = t

    def has(self, *names: str) -> bool:
        return all(self.messages[name] for name in names)


def whole_set(ranges: list[Any], count: int, events: list[tuple[float, Any]] | None = None) -> list[Any]:
    """The first reading set (one stamp) with all ``count`` sensors, in order, or [] (the
    subscription may have matched in the middle of a set's burst, or the newest set may be
    half taken); with ``events``, the first whose WURDE twin is among them."""
    sets: dict[float, list[Any]] = {}
    for r in ranges:
        sets.setdefault(stamp(r), []).append(r)
    return next((s for t, s in sets.items() if len(s) == count
                 and (events is None or same_stamp(events, t) is not None)), [])


def mounted(frames: dict[str, Any], frame: str, x: float, y: float, z: float, yaw: float = 0.0) -> None:
    t = frames[frame]
    assert t.header.frame_id == 'base_link', frame
    tr, q = t.transform.translation, t.transform.rotation
    assert (tr.x, tr.y, tr.z) == pytest.approx((x, y, z), abs=1e-9), frame
    assert math.remainder(2 * math.atan2(q.z, q.w) - yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-9), frame
    assert (q.x, q.y) == (0.0, 0.0), frame


def stamp(message: Any) -> float:
    return message.header.stamp.sec + message.header.stamp.nanosec * 1e-9


def one_period_apart(imus: list[Any], period: float) -> list[Any]:
    """The Imu messages that came one DMU period after the one before (none missed between)."""
    return [b for a, b in zip(imus, imus[1:]) if abs(stamp(b) - stamp(a) - period) < 1e-4]


def same_stamp(events: list[tuple[float, Any]], t: float) -> Any:
    """The WURDE event stamped ``t``, or None: each subscription matches in its own time, so a
    standard message's twin may have come before the observer listened, or not be taken yet."""
    return next((event for when, event in events if abs(when - t) < 1e-6), None)


def twinned(messages: list[Any], events: list[tuple[float, Any]]) -> list[tuple[Any, Any]]:
    """(standard message, WURDE event) pairs with one stamp, in order."""
    pairs = [(m, same_stamp(events, stamp(m))) for m in messages]
    return [(m, e) for m, e in pairs if e is not None]


@pytest.fixture
def robot(ros_domain: int, tmp_path: pathlib.Path) -> Iterator[pathlib.Path]:
    """The five dummies of config/sim with odometry and DMU noise on, each a process."""
    path = sim_config(tmp_path, elements={'odometry-noise': {'trans': str(TRANS_NOISE), 'rot': '0.05'},
                                          'dmu': {'rate-noise': str(RATE_NOISE)}})
    with ExitStack() as stack:
        for exe, name in (('dummy_base', 'PlutoBase'), ('dummy_sick', 'PlutoLaser'), ('dummy_wrist', 'PlutoWrist'),
                          ('dummy_dmu', 'PlutoDMU'), ('dummy_gps', 'PlutoGPS')):
            stack.enter_context(ChildProcess([find_executable('wurde_drivers', exe), '-c', str(path), '-n', name]))
        yield path


def test_every_dummy_device_is_on_a_standard_topic_with_its_frame_and_covariance(robot: pathlib.Path) -> None:
    from geometry_msgs.msg import Twist
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import BatteryState, Imu, JointState, NavSatFix, Range
    config = load_sim_config(robot)
    observer = Observer({'PlutoBaseSonar': 'RangeFinder', 'PlutoBaseBumpers': 'Bumper', 'PlutoBasePower': 'Power',
                         'PlutoBaseTruth': 'Egomotion', 'PlutoBaseMotion': 'Egomotion', 'PlutoWrist': 'ActuatorState',
                         'PlutoGPS': 'GPS'})
    node = observer.manager.node
    topics = Topics(node, {'/PlutoBase/sonar': Range, '/PlutoBase/bumpers': Range,
                           '/PlutoBase/battery': BatteryState, '/PlutoBase/ground_truth/odom': Odometry,
                           '/PlutoBase/odom': Odometry, '/PlutoWrist/joint_states': JointState,
                           '/PlutoDMU/imu': Imu, '/PlutoGPS/fix': NavSatFix})
    sonar = config.robot.sonar
    frames = ([f'PlutoBaseSonar_{i}' for i in range(sonar.count)] + ['PlutoBaseBumpers_0', 'PlutoBaseBumpers_1']
              + ['PlutoLaser', 'PlutoDMU', 'PlutoGPS', 'PlutoWrist'])

    def everything(o: Observer) -> bool:
        topics.take()
        return (topics.has(*[n for n in topics.messages if n != '/tf_static']) and set(frames) <= set(topics.frames)
                and whole_set(topics.messages['/PlutoBase/sonar'], sonar.count, o.events['PlutoBaseSonar'])
                and whole_set(topics.messages['/PlutoBase/bumpers'], 2)
                and 'PlutoBasePower' in o.infos
                and twinned(topics.messages['/PlutoBase/battery'], o.events['PlutoBasePower'])
                and twinned(topics.messages['/PlutoBase/ground_truth/odom'], o.events['PlutoBaseTruth'])
                and all(o.events[s] for s in ('PlutoBaseSonar', 'PlutoBasePower', 'PlutoWrist'))
                # A loaded machine's DMU can step late for a while (r95: no such pair yet).
                and bool(one_period_apart(topics.messages['/PlutoDMU/imu'], 1.0 / config.dmu.rate)))
    try:
        observer.until(everything, 'every standard topic and every mounting', timeout=60)
        # /tf_static: every mounting with the config's numbers (sonar ring, bumpers at the base's
        # radius 0.2 m up, the laser, DMU, GPS and wrist at their mount-* attributes).
        for i in range(sonar.count):
            a = 2 * math.pi * i / sonar.count
            mounted(topics.frames, f'PlutoBaseSonar_{i}', sonar.radius * math.cos(a), sonar.radius * math.sin(a),
                    sonar.mount_z, a)
        radius = config.robot.bumpers.radius
        mounted(topics.frames, 'PlutoBaseBumpers_0', radius, 0.0, 0.2)
        mounted(topics.frames, 'PlutoBaseBumpers_1', -radius, 0.0, 0.2, math.pi)
        laser = config.lasers['PlutoLaser']
        mounted(topics.frames, 'PlutoLaser', laser.mount_x, laser.mount_y, laser.mount_z)
        assert (laser.mount_x, laser.mount_z) == (0.2, 0.5)
        for frame, mount in (('PlutoDMU', config.dmu.mount), ('PlutoGPS', config.gps.mount),
                             ('PlutoWrist', config.wrist.mount)):
            mounted(topics.frames, frame, mount.x, mount.y, mount.z, mount.yaw)
        assert (config.wrist.mount.x, config.wrist.mount.z, config.gps.mount.z) == (0.15, 0.7, 0.9)

        # Sonar: one Range per transducer in its own frame, the values of the WURDE stream.
        ranges = topics.messages['/PlutoBase/sonar']
        ring = whole_set(ranges, sonar.count, observer.events['PlutoBaseSonar'])
        first = stamp(ring[0])
        assert [r.header.frame_id for r in ring] == [f'PlutoBaseSonar_{i}' for i in range(sonar.count)]
        wurde = same_stamp(observer.events['PlutoBaseSonar'], first)
        assert [r.range for r in ring] == pytest.approx(list(wurde.ranges), abs=1e-6)
        assert all(r.radiation_type == Range.ULTRASOUND and r.field_of_view == pytest.approx(2 * sonar.half_angle)
                   and r.max_range == pytest.approx(sonar.max_range) and r.min_range == 0.0 for r in ring)
        # Bumpers: fixed-distance rangers, +inf while not pressed (the robot stands free).
        bumpers = whole_set(topics.messages['/PlutoBase/bumpers'], 2)
        assert [b.header.frame_id for b in bumpers] == ['PlutoBaseBumpers_0', 'PlutoBaseBumpers_1']
        assert all(b.range == math.inf and b.min_range == b.max_range == 0.0 for b in bumpers)

        # Battery: the Power stream in BatteryState's units, NaN where unknown.
        battery, power = twinned(topics.messages['/PlutoBase/battery'], observer.events['PlutoBasePower'])[0]
        info = observer.infos['PlutoBasePower']
        assert battery.voltage == pytest.approx(power.voltage, rel=1e-6)
        assert battery.current == pytest.approx(-power.current, rel=1e-6, abs=1e-6)
        assert battery.percentage == pytest.approx(power.charge, rel=1e-6) and 0.0 < battery.percentage <= 1.0
        capacity_ah = info.capacity / info.nominal_voltage / 3600
        assert battery.capacity == pytest.approx(capacity_ah, rel=1e-6)
        assert battery.charge == pytest.approx(power.charge * capacity_ah, rel=1e-5)
        assert math.isnan(battery.temperature) and battery.present
        assert battery.power_supply_status == BatteryState.POWER_SUPPLY_STATUS_DISCHARGING
        assert battery.header.frame_id == 'base_link'

        # Ground truth: its own topic, frame map, equal to the Truth stream.
        truth, true = twinned(topics.messages['/PlutoBase/ground_truth/odom'], observer.events['PlutoBaseTruth'])[-1]
        assert (truth.header.frame_id, truth.child_frame_id) == ('map', 'base_link')
        assert (truth.pose.pose.position.x, truth.pose.pose.position.y) == pytest.approx(
            (true.location.x, true.location.y), abs=1e-9)

        # Imu and NavSatFix: covariances from the DMU's rate noise and the fix's HDOP/quality.
        imus = topics.messages['/PlutoDMU/imu']
        imu = imus[-1]
        assert imu.header.frame_id == 'PlutoDMU'
        # The low-pass lowers the rate's variance by the factor of the interval it stepped over:
        # the DMU's period, or longer where a loaded machine's DMU stepped late (up to the raw
        # noise, never above).  Exact where two messages came one period apart (none missed).
        assert all(MIN_VARIANCE < m.angular_velocity_covariance[8] <= (MIN_VARIANCE + RATE_NOISE ** 2) * (1 + 1e-9)
                   for m in imus), [m.angular_velocity_covariance[8] for m in imus]
        period, tau = 1.0 / config.dmu.rate, 1.0 / (2.0 * math.pi * config.dmu.cutoff)
        nominal = one_period_apart(imus, period)
        assert nominal, 'no two DMU messages one period apart'
        lowered = MIN_VARIANCE + RATE_NOISE ** 2 * lowpass_variance_factor(period, tau)
        # (rel 1e-3: a stamp near 1.8e9 s carries about 2e-7 s of rounding into the interval)
        assert all(m.angular_velocity_covariance[8] == pytest.approx(lowered, rel=1e-3) for m in nominal), \
            (lowered, [m.angular_velocity_covariance[8] for m in nominal])
        assert lowered < RATE_NOISE ** 2
        assert all(v >= MIN_VARIANCE for v in (imu.orientation_covariance[0], imu.orientation_covariance[8],
                                               imu.linear_acceleration_covariance[0]))
        fix = topics.messages['/PlutoGPS/fix'][0]
        gps = config.gps
        assert fix.header.frame_id == 'PlutoGPS'
        assert fix.position_covariance_type == NavSatFix.COVARIANCE_TYPE_APPROXIMATED
        assert list(fix.position_covariance) == pytest.approx(fix_covariance(gps.quality, gps.hdop))
        # DGPS: 0.1 m at HDOP 1 (nmea_navsat_driver's table)
        assert fix.position_covariance[0] == pytest.approx(MIN_VARIANCE + (gps.hdop * 0.1) ** 2)

        # Wrist: JointState equals the stream's pan and tilt (commanded somewhere first).
        observer.request('PlutoWrist', cmd_flags=0, position=[0.5, -0.2], velocity=[1.0, 1.0],
                         acceleration=[2.0, 2.0])

        def moved(o: Observer) -> bool:
            topics.take()
            pairs = twinned(topics.messages['/PlutoWrist/joint_states'], o.events['PlutoWrist'])
            return len(pairs) >= 5 and any(m.position[0] == pytest.approx(0.5, abs=1e-6) for m, _ in pairs)
        observer.until(moved, 'the wrist at pan 0.5 on joint_states', timeout=30)
        for joints, state in twinned(topics.messages['/PlutoWrist/joint_states'], observer.events['PlutoWrist'])[-5:]:
            assert list(joints.name) == ['PlutoWrist_pan', 'PlutoWrist_tilt']
            assert list(joints.position) == pytest.approx(list(state.position[:2]), rel=1e-6, abs=1e-7)
            assert list(joints.velocity) == pytest.approx(list(state.velocity[:2]), rel=1e-6, abs=1e-7)

        # Odometry: the pose covariance grows as the simulator's noise says while driving
        # straight ahead (east along the corridor): var(x) = trans² · distance.
        odom = topics.messages['/PlutoBase/odom'][0]
        x0 = odom.pose.pose.position.x
        assert odom.pose.covariance[0] == pytest.approx(MIN_VARIANCE) and odom.twist.covariance[0] >= MIN_VARIANCE
        cmd_vel = node.create_publisher(Twist, '/PlutoBase/cmd_vel', 10)
        forward = Twist()
        forward.linear.x = 0.5

        def driven(o: Observer) -> bool:
            cmd_vel.publish(forward)
            topics.take()
            return topics.messages['/PlutoBase/odom'][-1].pose.pose.position.x > x0 + 0.5
        observer.until(driven, 'half a metre driven', timeout=30)
        odom = topics.messages['/PlutoBase/odom'][-1]
        distance = odom.pose.pose.position.x - x0
        assert odom.pose.covariance[0] == pytest.approx(MIN_VARIANCE + TRANS_NOISE ** 2 * distance, rel=0.02)
        assert odom.pose.covariance[14] >= 1e5          # z: not measured
        moving = [m for m in topics.messages['/PlutoBase/odom'] if m.twist.twist.linear.x > 0.4]
        assert moving and all(m.twist.covariance[0] > MIN_VARIANCE for m in moving)
    finally:
        observer.close()


def test_the_ptu_server_publishes_joint_states_and_its_mounting(ros_domain: int, tmp_path: pathlib.Path) -> None:
    from sensor_msgs.msg import JointState
    with Ptu46Emulator() as unit:
        config = tmp_path / 'ptu-config.xml'
        config.write_text(f'<?xml version="1.0"?>\n<ptu-config>\n  <device port="{unit.path}" name="PTU" rate="10" '
                          'mount-x="0.1" mount-y="-0.05" mount-z="0.8" mount-yaw="0.3"/>\n</ptu-config>\n')
        observer = Observer({'PTU': 'PTUnit'})
        topics = Topics(observer.manager.node, {'/PTU/joint_states': JointState})
        try:
            with ChildProcess([find_executable('wurde_drivers', 'ptu_server'), '-c', str(config), '-n', 'PTU']):
                observer.until(lambda o: o.events['PTU'] and 'PTU' in o.infos, 'PTU data')
                observer.request('PTU', pan=0.4, tilt=-0.2, pan_speed=1.0, tilt_speed=1.0)

                def there(o: Observer) -> bool:
                    topics.take()
                    pairs = twinned(topics.messages['/PTU/joint_states'], o.events['PTU'])
                    return 'PTU' in topics.frames and len(pairs) >= 3 and any(
                        m.position[0] == pytest.approx(0.4, abs=0.01) for m, _ in pairs)
                observer.until(there, 'the PTU at pan 0.4 on joint_states, and its frame', timeout=30)
            mounted(topics.frames, 'PTU', 0.1, -0.05, 0.8, 0.3)
            for joints, data in twinned(topics.messages['/PTU/joint_states'], observer.events['PTU'])[-3:]:
                assert list(joints.name) == ['PTU_pan', 'PTU_tilt']
                assert list(joints.position) == pytest.approx([data.pan, data.tilt], rel=1e-6)
                assert list(joints.velocity) == pytest.approx([data.pan_velocity, data.tilt_velocity], rel=1e-6)
        finally:
            observer.close()
    assert unit.error is None


def test_the_real_laser_dmu_and_gps_drivers_publish_their_mountings_and_covariances(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """sick_server, dmu_module and gps_module on their emulators: frames from the device configs'
    ``mount-*``, the DMU's stated noise figures and the fix's HDOP in the covariances."""
    from sensor_msgs.msg import Imu, LaserScan, NavSatFix

    from wurde_drivers.dmu.emulator import DmuEmulator
    from wurde_drivers.dmu.module import NOISE
    from wurde_drivers.gps.emulator import GpsEmulator
    from wurde_drivers.sick.emulator import SickEmulator

    def config(kind: str, device: str) -> str:
        path = tmp_path / f'{kind}-config.xml'
        path.write_text(f'<?xml version="1.0"?>\n<{kind}-config>\n  {device}\n</{kind}-config>\n')
        return str(path)

    with ExitStack() as stack:
        laser = stack.enter_context(SickEmulator())
        dmu = stack.enter_context(DmuEmulator())
        gps = stack.enter_context(GpsEmulator(quality=2, hdop=1.5, rate_hz=5.0))
        configs = {
            'sick_server': ('laser', config('laser', f'<device port="{laser.path}" name="laser" type="LMS" '
                                                     'mount-x="0.25" mount-y="-0.1" mount-z="0.45"/>')),
            'dmu_module': ('PlutoDMU', config('dmu', f'<device port="{dmu.path}" name="PlutoDMU" '
                                                     'mount-x="-0.05" mount-z="0.3"/>')),
            'gps_module': ('PlutoGPS', config('gps', f'<device port="{gps.path}" name="PlutoGPS" '
                                                     'mount-x="-0.1" mount-y="0.05" mount-z="0.9"/>')),
        }
        observer = Observer(heartbeat('PlutoGPS'))   # a stream, so that the node exists
        topics = Topics(observer.manager.node, {'/laser/scan': LaserScan, '/PlutoDMU/imu': Imu,
                                                '/PlutoGPS/fix': NavSatFix})
        try:
            for exe, (name, path) in configs.items():
                stack.enter_context(ChildProcess([find_executable('wurde_drivers', exe), '-c', path, '-n', name]))

            def everything(o: Observer) -> bool:
                topics.take()
                return topics.has('/laser/scan', '/PlutoDMU/imu', '/PlutoGPS/fix') and len(
                    topics.messages['/PlutoDMU/imu']) >= 3 and {'laser', 'PlutoDMU', 'PlutoGPS'} <= set(topics.frames)
            observer.until(everything, 'a scan, Imu, fix and the three mountings', timeout=60)
            mounted(topics.frames, 'laser', 0.25, -0.1, 0.45)
            mounted(topics.frames, 'PlutoDMU', -0.05, 0.0, 0.3)
            mounted(topics.frames, 'PlutoGPS', -0.1, 0.05, 0.9)
            assert topics.messages['/laser/scan'][0].header.frame_id == 'laser'
            imu = topics.messages['/PlutoDMU/imu'][-1]
            assert imu.orientation_covariance[0] == pytest.approx(MIN_VARIANCE + NOISE.angle ** 2)
            # After the low-pass: below the raw noise at the DMU's rate, and never above it — a
            # sample after a gap (a loaded machine) has had no filtering and says so.
            imus = topics.messages['/PlutoDMU/imu']
            rates = [m.angular_velocity_covariance[0] for m in imus]
            accels = [m.linear_acceleration_covariance[8] for m in imus]
            assert MIN_VARIANCE < min(rates) < NOISE.rate ** 2 and max(rates) <= MIN_VARIANCE + NOISE.rate ** 2
            assert MIN_VARIANCE < min(accels) < NOISE.accel ** 2 and max(accels) <= MIN_VARIANCE + NOISE.accel ** 2
            assert imu.orientation_covariance[8] > MIN_VARIANCE                     # the heading's random walk
            fix = topics.messages['/PlutoGPS/fix'][0]
            assert fix.position_covariance_type == NavSatFix.COVARIANCE_TYPE_APPROXIMATED
            assert fix.position_covariance[0] == pytest.approx(MIN_VARIANCE + (1.5 * 0.1) ** 2)
            assert fix.position_covariance[8] == pytest.approx(MIN_VARIANCE + (2 * 1.5 * 0.1) ** 2)
        finally:
            observer.close()


def test_the_rflex_driver_mirrors_sonar_bumpers_battery_and_places_them(ros_domain: int,
                                                                       tmp_path: pathlib.Path) -> None:
    """rflex_server on the emulated B21r: 48 sonars and 14 bumper panels each in its frame at the
    robot's documented position, the battery with its unmeasured current NaN."""
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import BatteryState, Range

    from wurde_drivers.rflex.emulator import RFlexEmulator
    from wurde_drivers.rflex.module import BUMPER_RINGS
    from wurde_drivers.rflex.robots import B21R
    ranges = [0.5 + 0.05 * i for i in range(len(B21R.sonars))]
    with RFlexEmulator(B21R, voltage=25.5, sonar_ranges=lambda: ranges) as emulator:
        config = tmp_path / 'rflex-config.xml'
        config.write_text(f'<?xml version="1.0"?>\n<rflex-config>\n  <device port="{emulator.path}" name="base" '
                          'type="B21r"/>\n</rflex-config>\n')
        observer = Observer({'basePower': 'Power'})
        topics = Topics(observer.manager.node, {'/base/sonar': Range, '/base/bumpers': Range,
                                                '/base/battery': BatteryState, '/base/odom': Odometry})
        try:
            with ChildProcess([find_executable('wurde_drivers', 'rflex_server'), '-c', str(config), '-n', 'base']):
                def everything(o: Observer) -> bool:
                    topics.take()
                    return (bool(whole_set(topics.messages['/base/sonar'], 48))
                            and topics.has('/base/battery', '/base/odom')
                            and bool(whole_set(topics.messages['/base/bumpers'], 14))
                            and len(topics.frames) >= 48 + 14)
                observer.until(everything, 'a sonar ring, the bumpers, the battery and the frames', timeout=30)
        finally:
            observer.close()
    for i, sonar in enumerate(B21R.sonars):
        mounted(topics.frames, f'baseSonar_{i}', sonar.x, sonar.y, sonar.z, sonar.yaw)
    for i, panel in enumerate(B21R.bumpers):
        radius, z = BUMPER_RINGS[panel.ring]
        mounted(topics.frames, f'baseBumpers_{i}', radius * math.cos(panel.yaw), radius * math.sin(panel.yaw), z,
                panel.yaw)
    ring = whole_set(topics.messages['/base/sonar'], 48)
    assert [r.header.frame_id for r in ring] == [f'baseSonar_{i}' for i in range(48)]
    assert [r.range for r in ring] == pytest.approx(ranges, abs=2e-3)
    assert all(r.max_range == 10.0 and r.field_of_view == pytest.approx(math.radians(25)) for r in ring)
    assert all(b.range == math.inf for b in topics.messages['/base/bumpers'])
    battery = topics.messages['/base/battery'][-1]
    assert battery.voltage == pytest.approx(25.5, abs=0.01) and math.isnan(battery.current)
    assert 0.0 < battery.percentage <= 1.0 and battery.capacity == pytest.approx(24.0 * 3600 * 40 / 24.0 / 3600)
    odom = topics.messages['/base/odom'][-1]
    assert odom.pose.covariance[0] >= MIN_VARIANCE and odom.twist.covariance[35] >= MIN_VARIANCE
