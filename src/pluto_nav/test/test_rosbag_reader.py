"""The rosbag2 reader (:mod:`pluto_nav.logs.rosbag`): one recording (bag_scene: three lasers of
1081 beams over 270 degrees, mounted through a chain of frames, upside down and clockwise; two
Odometry topics; an IMU; /tf; custom types) written as bags in every layout gives the same records,
each checked against the scene in 3-D; damaged and unusable bags give counted problems or a
LogError naming the file, never a traceback.  No ROS process: rclpy only serializes."""

from __future__ import annotations

import math
import pathlib
import re
import shutil

import bag_scene as scene
import numpy as np
import pytest
from mcap.reader import make_reader
from scipy.spatial.transform import Rotation

from pluto_nav.logs import ImuRecord, LogError, LogProblems, OdometryRecord, ScanRecord, load_log
from pluto_nav.logs.rosbag import read_rosbag

BLOB_SKIPPED = f'message of the type {scene.BLOB} that cannot be read'
CHOSEN = 'odometry topic chosen'
SCANS = {'/scan': 20, '/scan_rear': 10, '/scan_cw': 5}


def read(path: pathlib.Path) -> tuple[list, LogProblems, list[str]]:
    warnings: list[str] = []
    problems = LogProblems(warnings.append)
    return list(read_rosbag(path, problems)), problems, warnings


def same_angle(a: float, b: float) -> bool:
    return abs(math.remainder(a - b, math.tau)) < 1e-9


def laser_pose(frame: str) -> tuple[Rotation, np.ndarray]:
    """The laser frame's pose on base_link, composed from the scene's mounts (scipy, 3-D)."""
    rotation, translation = Rotation.identity(), np.zeros(3)
    while frame in scene.MOUNTS:
        parent, xyz, rpy = scene.MOUNTS[frame]
        mount = Rotation.from_euler('xyz', rpy)
        rotation, translation = mount * rotation, mount.apply(translation) + np.array(xyz)
        frame = parent
    return rotation, translation


def assert_scan(record: ScanRecord, frame: str, clockwise: bool = False) -> None:
    """Every beam of ``record`` points where the scene's beam does (the beam is known by its
    remission, 2 x its index in the message), with its range read by the records' rules."""
    rotation, translation = laser_pose(frame)
    assert record.config.mount[:2] == pytest.approx(translation[:2], abs=1e-9)
    assert record.config.angular_resolution > 0 and record.config.max_range == scene.RANGE_MAX
    assert record.config.min_range == pytest.approx(scene.RANGE_MIN)
    assert len(record.ranges) == scene.BEAMS and record.remissions is not None
    source = (record.remissions / 2).astype(int)
    increment = scene.FOV / (scene.BEAMS - 1)
    laser_angles = (scene.FOV / 2 - increment * source) if clockwise else (-scene.FOV / 2 + increment * source)
    beams = rotation.apply(np.stack([np.cos(laser_angles), np.sin(laser_angles), np.zeros(scene.BEAMS)], axis=1))
    expected = np.arctan2(beams[:, 1], beams[:, 0])
    got = record.config.mount[2] + record.angles
    assert np.abs(np.angle(np.exp(1j * (got - expected)))).max() < 1e-5
    ranges = scene.ramp().astype(np.float64)
    ranges[:len(scene.SPECIAL_READ)] = scene.SPECIAL_READ
    np.testing.assert_array_equal(record.ranges, ranges[source])


def assert_scene(records: list, problems: LogProblems, blob: int = 7, status: int = 0) -> None:
    assert [r.stamp for r in records] == sorted(r.stamp for r in records)
    scans = {topic: [r for r in records if isinstance(r, ScanRecord) and r.channel == topic] for topic in SCANS}
    assert {topic: len(s) for topic, s in scans.items()} == SCANS
    assert len([r for r in records if isinstance(r, ScanRecord)]) == sum(SCANS.values())
    for topic, first, step in (('/scan', 0.1, 0.1), ('/scan_rear', 0.15, 0.2), ('/scan_cw', 0.2, 0.5)):
        assert [s.stamp for s in scans[topic]] == pytest.approx([scene.T0 + first + step * k
                                                                 for k in range(SCANS[topic])], abs=1e-6)
    assert_scan(scans['/scan'][0], 'laser')
    np.testing.assert_array_equal(scans['/scan'][-1].ranges[:7], scene.SPECIAL_READ)     # in order
    assert scans['/scan'][0].config.start_angle == pytest.approx(-scene.FOV / 2)
    assert_scan(scans['/scan_rear'][0], 'rear_laser')                      # upside down: reversed
    assert scans['/scan_rear'][0].config.mount[:2] == pytest.approx((-0.30, 0.05))
    assert same_angle(scans['/scan_rear'][0].config.mount[2], math.pi)
    assert_scan(scans['/scan_cw'][-1], 'base_link', clockwise=True)       # the base frame itself
    assert scans['/scan_cw'][0].config.mount == (0.0, 0.0, 0.0)
    odometry = [r for r in records if isinstance(r, OdometryRecord)]
    assert len(odometry) == 30 and {r.origin.rsplit(':', 1)[1] for r in odometry} == {'/odom'}
    for k, record in enumerate(odometry):
        assert record.stamp == pytest.approx(scene.T0 + 0.05 * k, abs=1e-6)
        assert record.pose == pytest.approx(scene.odometry_pose(k), abs=1e-9)
        assert (record.tv, record.rv) == (0.5, 0.1)
    imu = [r for r in records if isinstance(r, ImuRecord)]
    assert len(imu) == 15
    for k, record in enumerate(imu):
        assert record.yaw == pytest.approx(0.03 * k, abs=1e-9)
        assert record.angular_velocity == (0.0, 0.0, 0.1) and record.linear_acceleration == (9.81, 0.0, 0.0)
    assert len(records) == sum(SCANS.values()) + 30 + 15
    skipped = {BLOB_SKIPPED: blob, f'message of the type {scene.STATUS} that cannot be read': status}
    assert dict(problems.counts) == {CHOSEN: 1, **{kind: n for kind, n in skipped.items() if n}}
    assert problems.errors == []


WRITERS = {
    'sqlite3': lambda path: scene.write_rosbags(path, scene.full_scene()),
    'mcap': lambda path: scene.write_rosbags(path, scene.full_scene(), storage='mcap'),
    'sqlite3, no definitions': lambda path: scene.write_rosbags(path, scene.full_scene(), definitions=False),
    'sqlite3, zstd files': lambda path: scene.write_rosbags(path, scene.full_scene(), compression='file'),
    'mcap, zstd messages': lambda path: scene.write_rosbags(path, scene.full_scene(), storage='mcap',
                                                            compression='message'),
    'sqlite3, split': lambda path: scene.write_split(path, scene.full_scene(), scene.full_scene()[70].time_ns),
    'mcap, split': lambda path: scene.write_split(path, scene.full_scene(), scene.full_scene()[70].time_ns,
                                                  'mcap'),
}


@pytest.mark.parametrize('layout', list(WRITERS))
def test_a_bag_directory_gives_every_record(tmp_path: pathlib.Path, layout: str) -> None:
    bag = WRITERS[layout](tmp_path / 'bag')
    records, problems, warnings = read(bag)
    status = 3 if 'no definitions' in layout else 0                     # then Status cannot be read either
    assert_scene(records, problems, status=status)
    assert f'{bag}:/acme/blob: {BLOB_SKIPPED}' in warnings[0] and scene.BLOB in warnings[0]
    assert f'{bag}: {CHOSEN}: /odom of /odom (30), /odometry/filtered (40)' in warnings[-1]
    assert len(warnings) == 2 + bool(status)
    assert_scene(*read(bag / 'metadata.yaml')[:2], status=status)


@pytest.mark.parametrize('storage, name', [('sqlite3', 'alone.db3'), ('mcap', 'alone.mcap'),
                                           ('mcap', 'recording.bin'), ('sqlite3', 'recording')])
def test_a_storage_file_without_metadata_is_read_by_its_content(tmp_path: pathlib.Path, storage: str,
                                                                name: str) -> None:
    bag = scene.write_rosbags(tmp_path / 'bag', scene.full_scene(), storage=storage)
    single = tmp_path / name
    shutil.copy(next(p for p in bag.iterdir() if p.name != 'metadata.yaml'), single)
    records, problems, _ = read(single)
    assert_scene(records, problems)


def test_a_directory_of_split_files_without_metadata_is_read_as_one_bag(tmp_path: pathlib.Path) -> None:
    items = scene.full_scene()
    bag = scene.write_split(tmp_path / 'bag', items, items[70].time_ns)
    (bag / 'metadata.yaml').unlink()                                      # the recorder was killed
    (bag / 'bag_1.db3').rename(bag / 'bag_10.db3')                        # before bag_2 by name
    (bag / 'bag_0.db3').rename(bag / 'bag_2.db3')
    records, problems, _ = read(bag)
    assert_scene(records, problems)


def test_mcap_files_of_the_record_tool_and_of_mcap_ros2(tmp_path: pathlib.Path) -> None:
    recorded = scene.write_record_tool(tmp_path / 'record.mcap', scene.full_scene())
    records, problems, _ = read(recorded)
    assert_scene(records, problems)            # Blob recorded with an empty definition: unreadable
    written = scene.write_mcap_ros2(tmp_path / 'mcap_ros2.mcap', scene.full_scene())
    records, problems, _ = read(written)
    assert_scene(records, problems, blob=0)


@pytest.mark.parametrize('damage', ['cut short', 'zeros in a chunk'])
def test_a_damaged_mcap_file_gives_what_comes_before_the_damage(tmp_path: pathlib.Path, damage: str) -> None:
    full = scene.write_mcap_ros2(tmp_path / 'full.mcap', scene.full_scene(), chunk_size=16 * 1024)
    every = {(type(r).__name__, getattr(r, 'channel', ''), r.stamp) for r in read(full)[0]}
    data = full.read_bytes()
    damaged = tmp_path / 'damaged.mcap'
    with full.open('rb') as stream:
        chunks = make_reader(stream).get_summary().chunk_indexes      # type: ignore[union-attr]
    chunk = chunks[len(chunks) // 2]
    middle = chunk.chunk_start_offset + chunk.chunk_length // 2          # inside a chunk's data
    damaged.write_bytes(data[:middle] if damage == 'cut short' else data[:middle] + bytes(64) + data[middle + 64:])
    records, problems, warnings = read(damaged)
    assert 0 < len(records) < len(every)
    assert {(type(r).__name__, getattr(r, 'channel', ''), r.stamp) for r in records} <= every
    said = 'the MCAP file breaks off' if damage == 'cut short' else 'damaged after bag time'
    assert len(problems.errors) == 1 and problems.errors[0].startswith(f'{damaged}: {said}')
    assert problems.errors[0] in warnings


def test_without_odometry_the_odom_transforms_are_the_odometry(tmp_path: pathlib.Path) -> None:
    items = [i for i in scene.full_scene(custom=False)
             if i.topic in ('/tf_static', '/scan') or (i.topic == '/tf' and i.time_ns < 10**9 * scene.T0 + 5 * 10**8)]
    footprint = scene.transform(0.0, 'base_footprint', 'base_link', (0.05, 0.0, 0.1), (0.0, 0.0, 0.0))
    next(i for i in items if i.topic == '/tf_static').message.transforms.append(footprint)
    for item in items:
        if item.topic == '/tf':
            item.message.transforms[0].child_frame_id = 'base_footprint'
    records, problems, warnings = read(scene.write_rosbags(tmp_path / 'bag', items))
    odometry = [r for r in records if isinstance(r, OdometryRecord)]
    assert np.array([r.pose for r in odometry]) == pytest.approx(np.array([scene.odometry_pose(k) for k in range(5)]),
                                                                 abs=1e-9)
    forward = [(math.cos(0.02 * k) * 0.1 + math.sin(0.02 * k) * 0.01) / 0.1 for k in range(4)]
    assert [r.tv for r in odometry[1:]] == pytest.approx(forward, rel=1e-5)     # float stamps: 0.2 us
    assert [r.stamp - scene.T0 for r in odometry] == pytest.approx([0.03 + 0.1 * k for k in range(5)], abs=1e-6)
    assert [r.rv for r in odometry[1:]] == pytest.approx([0.2] * 4, rel=1e-5)
    scans = [r for r in records if isinstance(r, ScanRecord)]
    assert len(scans) == 20                    # the laser on base_footprint: base_link 5 cm ahead of it
    _, translation = laser_pose('laser')
    assert scans[0].config.mount[:2] == pytest.approx((translation[0] + 0.05, translation[1]), abs=1e-9)
    assert dict(problems.counts) == {'odometry from /tf': 1}
    assert 'odom -> base_footprint' in warnings[0]


def test_a_laser_frame_without_a_transform_to_the_base_is_counted_and_left_out(tmp_path: pathlib.Path) -> None:
    items = [i for i in scene.full_scene(custom=False) if i.topic in ('/tf_static', '/scan', '/odom', '/scan_cw')]
    for item in items:
        if item.topic == '/scan':
            item.message.header.frame_id = 'lost_laser'
    records, problems, warnings = read(scene.write_rosbags(tmp_path / 'bag', items))
    assert {r.channel for r in records if isinstance(r, ScanRecord)} == {'/scan_cw'}
    assert dict(problems.counts) == {'/scan scan with no transform to the base': 20}
    assert "'base_link'" in warnings[0] and "'lost_laser'" in warnings[0] and ':/scan:' in warnings[0]


def test_damaged_messages_and_stamps_are_counted_and_the_rest_read(tmp_path: pathlib.Path) -> None:
    items = [i for i in scene.full_scene(custom=False) if i.topic in ('/tf_static', '/scan', '/odom')]
    scans = [i for i in items if i.topic == '/scan']
    scans[3].message = b'\x00\x01\x00\x00' + b'\xff' * 12                 # cut off after 12 bytes
    scans[5].message.header.stamp = scene.stamp(0.0)                      # back in time
    scans[7].message.header.stamp.sec, scans[7].message.header.stamp.nanosec = 0, 0    # none at all
    bag = scene.write_rosbags(tmp_path / 'bag', items)
    records, problems, warnings = read(bag)
    got = [r for r in records if isinstance(r, ScanRecord)]
    assert len(got) == 19 and len(records) == 19 + 30
    assert [r.stamp for r in records] == sorted(r.stamp for r in records)
    assert any(r.stamp == pytest.approx(scans[7].time_ns * 1e-9) for r in got)   # the bag's time instead
    assert dict(problems.counts) == {'sensor_msgs/msg/LaserScan message that cannot be decoded': 1,
                                     'stamp going back on /scan': 1, 'message without a header stamp': 1}
    assert any(w.startswith(f'{bag}:/scan: sensor_msgs/msg/LaserScan message that cannot') for w in warnings)


def test_unusable_bags_raise_a_log_error_naming_the_file(tmp_path: pathlib.Path) -> None:
    items = scene.full_scene(custom=False)
    json = scene.write_rosbags(tmp_path / 'json', items, storage='mcap', formats={'/imu/data': 'json'})
    for path in (json, next(json.glob('*.mcap'))):
        with pytest.raises(LogError, match="json") as raised:
            read(path)
        assert str(raised.value).startswith(str(path))
    without_scans = scene.write_rosbags(tmp_path / 'no_scans', [i for i in items if i.topic == '/odom'])
    with pytest.raises(LogError,
                       match=r'no sensor_msgs/msg/LaserScan messages .*: /odom \(nav_msgs/msg/Odometry, 30\)$'):
        load_log(without_scans)
    empty = scene.write_rosbags(tmp_path / 'empty', [])
    with pytest.raises(LogError, match=re.escape(f'{empty}: an empty bag')):
        load_log(empty)
    damaged = tmp_path / 'damaged.db3'
    database = (scene.write_rosbags(tmp_path / 'whole', items) / 'whole.db3').read_bytes()
    damaged.write_bytes(database[:len(database) // 2])
    with pytest.raises(LogError, match=re.escape(f'{damaged}: not readable as a rosbag2 bag')):
        load_log(damaged)
    garbage = tmp_path / 'garbage.mcap'
    garbage.write_bytes(b'\x89MCAP0\r\n' + bytes(range(256)) * 4)
    warnings: list[str] = []
    with pytest.raises(LogError, match=re.escape(f'{garbage}: an empty bag')):
        load_log(garbage, warn=warnings.append)
    assert warnings and warnings[0].startswith(f'{garbage}: the MCAP file breaks off')


def test_load_log_gives_the_bag_as_a_robot_log(tmp_path: pathlib.Path) -> None:
    bag = scene.write_rosbags(tmp_path / 'bag', scene.full_scene(), storage='mcap')
    log = load_log(bag, warn=lambda _: None)
    assert log.lasers == SCANS and [s.channel for s in log.scans] == ['/scan'] * 20
    assert len(log.odometry) == 30 and log.odometry_source == 'odometry records' and len(log.imu) == 15
    assert (log.start, log.end) == pytest.approx((scene.T0, scene.T0 + 2.0), abs=1e-6)
    assert log.odometry_at(scene.T0 + 0.075) == pytest.approx((0.15, 0.015, 0.03), abs=1e-4)
    rear = load_log(bag, laser='/scan_rear', warn=lambda _: None)
    assert len(rear.scans) == 10 and same_angle(rear.scans[0].config.mount[2], math.pi)
