"""``carmen_log``: ``convert`` writes an MCAP bag that rosbags, mcap_ros2 and wurde_mcp's ``replay``
read back with the log's values; ``play`` is a real module process whose streams a real consumer
(in this process) receives whole and correct, as fast as it takes them (``-R 0``) and at a pace;
a missing or unreadable log is one line naming the file, never a traceback."""

from __future__ import annotations

import math
import pathlib
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
import yaml

from carmen_scene import DEG, flaser, odom, write
from nav_fixture import Watcher, seconds
from wurde_testing import ChildProcess, find_executable

ODOMETRY, SCANS, REAR = 40, 12, 4


def scan_ranges(i: int) -> list[float]:
    """181 beams; beam 3 saw nothing (the SICK's 81.91), beam 4 is the laser's 0 (no reading)."""
    values = [1.0 + 0.01 * b + 0.1 * i for b in range(181)]
    values[3], values[4] = 81.91, 0.0
    return values


def small_log(directory: pathlib.Path, *, step: float = 0.05) -> pathlib.Path:
    """ODOM every ``step`` s, FLASER (181 beams, the laser 0.2 m ahead) every 3rd, RLASER, TRUEPOS."""
    lines = ['# CARMEN Logfile', 'PARAM robot_frontlaser_offset 0.2 0.0 host 0.0',
             'PARAM robot_rearlaser_offset 0.15 0.0 host 0.0', 'SYNC start 0.0 host 0.0']
    for i in range(ODOMETRY):
        t = 100.0 + step * i
        lines.append(odom(t, x=0.01 * i, y=0.002 * i, theta=0.01 * i, tv=0.2, rv=0.05))
        if i % 3 == 1 and i // 3 < SCANS:
            lines.append(flaser(t + 0.001, scan_ranges(i // 3), robot=(0.01 * i, 0.002 * i, 0.01 * i)))
        if i % 10 == 2:
            lines.append(flaser(t + 0.002, 181, robot=(0.01 * i, 0.0, 0.0), name='RLASER'))
            lines.append(f'TRUEPOS {0.01 * i:.6f} 0.0 0.0 0.0 0.0 0.0 {t + 0.003:.6f} host 0.0')
    return write(directory / 'small.clf.gz', lines, compress=True)


def run(*args: str, timeout: float = 60.0) -> ChildProcess:
    """``carmen_log args`` run to its end."""
    child = ChildProcess([find_executable('pluto_nav', 'carmen_log'), *args])
    try:
        child.process.wait(timeout=timeout)
    finally:
        child.stop()
    return child


# -- convert -----------------------------------------------------------------------------------------
@pytest.mark.process
def test_convert_writes_a_rosbag2_mcap_that_reads_back(tmp_path: pathlib.Path) -> None:
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader

    out = tmp_path / 'out' / 'small.mcap'
    child = run('convert', str(small_log(tmp_path)), str(out))
    assert child.process.returncode == 0, child.stderr
    assert f'wrote {out}: 40 on /odom, 4 on /rear_scan, {SCANS} on /scan, 40 on /tf, 1 on /tf_static, 4 on /truth' \
        in child.stdout, child.stdout
    with out.open('rb') as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == 'ros2'
        summary = reader.get_summary()
        assert summary is not None
        channels = {c.topic: c for c in summary.channels.values()}
        for channel in channels.values():
            schema = summary.schemas[channel.schema_id]
            assert channel.message_encoding == 'cdr' and schema.encoding == 'ros2msg'
            assert schema.name in ('sensor_msgs/msg/LaserScan', 'nav_msgs/msg/Odometry', 'tf2_msgs/msg/TFMessage')
            assert b'\nMSG: builtin_interfaces/Time\n' in schema.data     # the full definition
            qos = yaml.safe_load(channel.metadata['offered_qos_profiles'])
            latched = channel.topic == '/tf_static'
            assert qos[0]['durability'] == ('transient_local' if latched else 'volatile')
            assert qos[0]['reliability'] == 'reliable' and channel.metadata['topic_type_hash'].startswith('RIHS01_')
            assert channel.metadata['durability'] == ('transient_local' if latched else 'volatile')
        in_file = [m.log_time for _, _, m in reader.iter_messages(log_time_order=False)]
        assert in_file == sorted(in_file)
    messages: dict[str, list[Any]] = {}                 # decoded by the schemas in the file
    with out.open('rb') as stream:
        for _, channel, message, decoded in make_reader(stream, decoder_factories=[DecoderFactory()]) \
                .iter_decoded_messages(log_time_order=True):
            messages.setdefault(channel.topic, []).append((message, decoded))
    assert {t: len(m) for t, m in messages.items()} == {'/tf_static': 1, '/scan': SCANS, '/rear_scan': REAR,
                                                         '/odom': ODOMETRY, '/tf': ODOMETRY, '/truth': 4}
    scan = messages['/scan'][1][1]
    assert scan.header.frame_id == 'laser' and seconds(scan) == pytest.approx(100.0 + 0.05 * 4 + 0.001)
    assert messages['/scan'][1][0].log_time == round((100.0 + 0.05 * 4 + 0.001) * 1e9)
    assert scan.angle_min == pytest.approx(-math.pi / 2) and scan.angle_increment == pytest.approx(DEG)
    assert scan.angle_max == pytest.approx(math.pi / 2) and scan.range_max == 80.0
    expected = np.array(scan_ranges(1), dtype=np.float32)
    expected[3], expected[4] = np.inf, np.nan
    np.testing.assert_array_equal(np.array(scan.ranges, dtype=np.float32), expected)
    static = {t.child_frame_id: t for t in messages['/tf_static'][0][1].transforms}
    assert static['laser'].header.frame_id == 'base_link'
    assert static['laser'].transform.translation.x == pytest.approx(0.2)
    rear = static['rear_laser'].transform
    assert rear.translation.x == pytest.approx(-0.15) and abs(rear.rotation.z) == pytest.approx(1.0)
    odometry = messages['/odom'][7][1]
    assert (odometry.header.frame_id, odometry.child_frame_id) == ('odom', 'base_link')
    assert odometry.pose.pose.position.x == pytest.approx(0.07)
    assert odometry.twist.twist.angular.z == pytest.approx(0.05)
    assert 2 * math.atan2(odometry.pose.pose.orientation.z, odometry.pose.pose.orientation.w) == pytest.approx(0.07)
    tf = messages['/tf'][7][1].transforms[0]
    assert (tf.header.frame_id, tf.child_frame_id) == ('odom', 'base_link')
    assert tf.transform.translation.x == pytest.approx(0.07)
    assert messages['/truth'][1][1].header.frame_id == 'map'
    assert messages['/truth'][1][1].pose.pose.position.x == pytest.approx(0.12)
    with AnyReader([out]) as bag:                     # rosbags reads it too, QoS and all
        counts = {c.topic: c.msgcount for c in bag.connections}
        assert counts['/scan'] == SCANS and counts['/odom'] == ODOMETRY
        assert {c.topic: c.ext.offered_qos_profiles[0].durability.name for c in bag.connections}['/tf_static'] \
            == 'TRANSIENT_LOCAL'


def test_replay_plays_the_converted_bag_to_a_subscriber(ros_domain: int, rclpy_context: Any,
                                                        tmp_path: pathlib.Path) -> None:
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import LaserScan
    from tf2_msgs.msg import TFMessage

    out = tmp_path / 'small.mcap'
    assert run('convert', str(small_log(tmp_path)), str(out)).process.returncode == 0
    node = rclpy.create_node('carmen_replay_check', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    scans: list[LaserScan] = []
    statics: list[TFMessage] = []
    node.create_subscription(LaserScan, '/scan', scans.append,
                             QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE))
    node.create_subscription(TFMessage, '/tf_static', statics.append,
                             QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                        durability=DurabilityPolicy.TRANSIENT_LOCAL))
    try:
        with ChildProcess([find_executable('wurde_mcp', 'replay'), str(out), '-r', '0', '-w', '30',
                           '-t', '^/(scan|tf_static)$']) as replay:
            replay.expect('replay: 2 topics', timeout=60)
            deadline = time.monotonic() + 60
            while (len(scans) < SCANS or not statics) and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.05)
            replay.expect(f'replay: {SCANS + 1} messages', timeout=30)
        assert len(scans) == SCANS and len(statics) == 1
        assert seconds(scans[0]) == pytest.approx(100.051) and math.isinf(scans[0].ranges[3])
        assert {t.child_frame_id for t in statics[0].transforms} == {'laser', 'rear_laser'}
    finally:
        executor.shutdown()
        node.destroy_node()


@pytest.mark.process
def test_convert_refuses_what_it_cannot_read_or_write(tmp_path: pathlib.Path) -> None:
    missing = tmp_path / 'missing.clf'
    child = run('convert', str(missing), str(tmp_path / 'x.mcap'))
    assert child.process.returncode == 2
    assert child.stderr.strip() == f'carmen_log: {missing}: cannot be read: No such file or directory'
    garbage = tmp_path / 'garbage.clf'
    garbage.write_bytes(bytes(range(256)) * 4)
    child = run('convert', str(garbage), str(tmp_path / 'x.mcap'))
    assert child.process.returncode == 2 and f'{garbage}: neither a CARMEN log' in child.stderr
    blocker = tmp_path / 'file'
    blocker.write_text('not a directory')
    child = run('convert', str(small_log(tmp_path)), str(blocker / 'x.mcap'))
    assert child.process.returncode == 1 and child.stderr.startswith(f'carmen_log: cannot write {blocker / "x.mcap"}')
    assert not (tmp_path / 'x.mcap').exists() and 'Traceback' not in child.stderr


# -- play --------------------------------------------------------------------------------------------
def _receive(watcher: Watcher, player: ChildProcess, expected: dict[str, int],
             arrivals: dict[str, list[float]], timeout: float) -> None:
    """Pump ``watcher`` until the player has exited and ``expected`` events have come per stream,
    noting when each arrived (monotonic)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        watcher.manager.step()
        now = time.monotonic()
        for stream, obj in watcher.objects.items():
            while obj.get_next_info():
                pass
            while obj.get_next_data():
                watcher.events[stream].append(obj.data.ros_message())
                arrivals[stream].append(now)
        if player.process.poll() is not None and all(len(watcher.events[s]) >= n for s, n in expected.items()):
            return
        watcher.manager.wait(0.02)
    raise AssertionError(f'not all events within {timeout} s: {[len(e) for e in watcher.events.values()]}; '
                         f'player exit code {player.process.poll()}\n{player.stdout}{player.stderr}')


def _play(tmp_path: pathlib.Path, expected: dict[str, int], *args: str, base: str = 'PlutoBase',
          laser: str = 'PlutoLaser', setup: Callable[[Watcher], None] = lambda _: None
          ) -> tuple[Watcher, ChildProcess, dict[str, list[float]]]:
    """``carmen_log play`` of :func:`small_log` to a consumer of ``<base>Motion``, ``<laser>`` and
    ``<laser>/Timing`` here (``setup`` adds more before the player starts); returns it with the
    player (ended) and the arrival times."""
    log = small_log(tmp_path)
    streams = {f'{base}Motion': 'Egomotion', laser: 'RangeFinder', f'{laser}/Timing': 'FVectorState'}
    watcher = Watcher(streams, name='CarmenLogTest')
    setup(watcher)
    arrivals: dict[str, list[float]] = {s: [] for s in streams}
    try:
        with ChildProcess([find_executable('pluto_nav', 'carmen_log'), 'play', str(log), *args, '-b', base,
                           '-s', laser, '-w', '30', '-n', 'carmenPlayer']) as player:
            _receive(watcher, player, {f'{base}Motion': expected['odometry'], laser: expected['scans']},
                     arrivals, timeout=90)
            assert player.process.wait(timeout=10) == 0, player.stderr
    except BaseException:
        watcher.close()
        raise
    return watcher, player, arrivals


def test_play_as_fast_as_the_reader_takes_it_loses_nothing(ros_domain: int, tmp_path: pathlib.Path) -> None:
    from nav_msgs.msg import Odometry
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import LaserScan
    from tf2_msgs.msg import TFMessage

    from wurde_core.ros_adaptor import polled, take

    mirrored: dict[str, list[Any]] = {'scan': [], 'odom': [], 'static': []}
    readers: dict[str, Any] = {}

    def subscribe(watcher: Watcher) -> None:
        # The mirrors' readers in the consumer's own node (drained by polling, as the streams'),
        # so the player, which waits for every reader it knows of, finds them with the streams'.
        node, reliable = watcher.manager.node, QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
        readers['scan'] = node.create_subscription(LaserScan, '/PlutoLaser/scan', polled, reliable)
        readers['odom'] = node.create_subscription(Odometry, '/PlutoBase/odom', polled, reliable)
        readers['static'] = node.create_subscription(
            TFMessage, '/tf_static', polled, QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                                        durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def drain() -> None:
        for key, reader in readers.items():
            mirrored[key] += take(reader)

    watcher, player, _ = _play(tmp_path, {'odometry': ODOMETRY, 'scans': SCANS}, '-R', '0', setup=subscribe)
    try:
        watcher.until(lambda: bool(mirrored['static']) and len(mirrored['scan']) >= 1 and len(mirrored['odom']) >= 1,
                      'the standard mirrors', timeout=10, every=drain)
        transform = mirrored['static'][-1].transforms[0]
        assert (transform.header.frame_id, transform.child_frame_id) == ('base_link', 'PlutoLaser')
        assert transform.transform.translation.x == pytest.approx(0.2)
        for scan in mirrored['scan']:
            k = round((seconds(scan) - 100.051) / 0.15)
            assert seconds(scan) == pytest.approx(100.0 + 0.05 * (3 * k + 1) + 0.001, abs=1e-6)
            assert scan.header.frame_id == 'PlutoLaser' and scan.angle_min == pytest.approx(-math.pi / 2)
            assert scan.ranges[0] == pytest.approx(1.0 + 0.1 * k) and math.isinf(scan.ranges[3])
        odometry = mirrored['odom'][-1]
        assert odometry.pose.pose.position.x == pytest.approx(0.01 * round((seconds(odometry) - 100.0) / 0.05))
    except BaseException:
        watcher.close()
        raise
    try:
        events = watcher.events
        assert len(events['PlutoBaseMotion']) == ODOMETRY and len(events['PlutoLaser']) == SCANS
        assert len(events['PlutoLaser/Timing']) == SCANS
        assert f'carmenPlayer: played {SCANS} scans (front laser) and {ODOMETRY} odometry records' in player.stdout
        assert 'log problems: no problems (ignored: 1 SYNC line)' in player.stdout
        for i, motion in enumerate(events['PlutoBaseMotion']):
            assert seconds(motion) == pytest.approx(100.0 + 0.05 * i, abs=1e-6)
            assert (motion.location.x, motion.location.y, motion.location.theta) == \
                pytest.approx((0.01 * i, 0.002 * i, 0.01 * i))
            assert (motion.tv, motion.rv) == pytest.approx((0.2, 0.05))
        for k, (scan, timing) in enumerate(zip(events['PlutoLaser'], events['PlutoLaser/Timing'])):
            stamp = 100.0 + 0.05 * (3 * k + 1) + 0.001
            assert seconds(scan) == pytest.approx(stamp, abs=1e-6) and seconds(timing) == pytest.approx(stamp, abs=1e-6)
            assert list(timing.element) == [181]
            expected = np.array(scan_ranges(k))
            expected[3], expected[4] = np.inf, np.nan
            np.testing.assert_allclose(np.array(scan.ranges), expected)
        info = watcher.objects['PlutoLaser'].info
        assert info.theta_offset.get_value() == pytest.approx(-math.pi / 2)
        assert info.theta_separation.get_value() == pytest.approx(DEG)
        assert info.half_angle.get_value() == pytest.approx(DEG / 2)
        assert info.x_offset.get_value() == pytest.approx(0.2) and info.max_range.get_value() == pytest.approx(80.0)
        assert info.uniform.get_value() is True
    finally:
        watcher.close()


def test_play_keeps_the_logs_pace_on_the_streams_named(ros_domain: int, tmp_path: pathlib.Path) -> None:
    # The log spans 39 x 0.05 s = 1.95 s; at -R 1.5 it takes 1.3 s, never less.  The rear laser
    # looks backwards from 0.15 m behind the centre: its fan starts at +90 degrees.
    watcher, player, arrivals = _play(tmp_path, {'odometry': ODOMETRY, 'scans': REAR}, '-R', '1.5', '-L', 'rear',
                                      base='Logged', laser='RearLaser')
    try:
        assert len(watcher.events['LoggedMotion']) == ODOMETRY and len(watcher.events['RearLaser']) == REAR
        span = arrivals['LoggedMotion'][-1] - arrivals['LoggedMotion'][0]
        assert span >= 1.95 / 1.5 - 0.15, f'played in {span:.2f} s'
        assert f'played {REAR} scans (rear laser)' in player.stdout
        info = watcher.objects['RearLaser'].info
        assert info.theta_offset.get_value() == pytest.approx(math.pi / 2)
        assert info.x_offset.get_value() == pytest.approx(-0.15)
    finally:
        watcher.close()


@pytest.mark.process
def test_play_refuses_a_log_it_cannot_read_in_one_line(tmp_path: pathlib.Path) -> None:
    missing = tmp_path / 'missing.clf.gz'
    child = run('play', str(missing), '-R', '0')
    assert child.process.returncode == 2
    assert child.stderr.strip() == f'carmen_log play: {missing}: cannot be read: No such file or directory'
    empty = write(tmp_path / 'empty.clf', [])
    empty.write_bytes(b'')
    child = run('play', str(empty))
    assert child.process.returncode == 2 and child.stderr.strip() == f'carmen_log play: {empty}: an empty file'
    child = run('play', str(small_log(tmp_path)), '-L', 'raw2')
    assert child.process.returncode == 2 and 'no scans of the laser raw2 (it has front, rear)' in child.stderr
    child = run('play', str(small_log(tmp_path)), '-R', 'fast')
    assert child.process.returncode == 2 and '-R fast: a number >= 0' in child.stderr
    assert 'Traceback' not in child.stderr
