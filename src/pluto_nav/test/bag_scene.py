"""A small robot recording written as rosbag2 bags in every way the reader must take them, and what
the reader must make of it.

The messages are real ROS 2 messages (rclpy's classes, serialized by rclpy: the bytes a robot's
recorder stores); the bags are written by rosbags' writer (sqlite3 and MCAP storage, compressed,
split by hand), by ``mcap_ros2``'s writer, and by this project's ``record`` tool's sink.
"""

from __future__ import annotations

import array
import dataclasses
import math
import pathlib
import shutil
from collections.abc import Sequence
from typing import Any

import numpy as np
import yaml
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Quaternion, TransformStamped
from nav_msgs.msg import Odometry
from rclpy.serialization import serialize_message
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import Imu, LaserScan
from tf2_msgs.msg import TFMessage

T0 = 1_700_000_000
BEAMS = 1081
FOV = math.radians(270.0)
RANGE_MIN, RANGE_MAX = 0.02, 30.0
LATENCY_NS = 5_000_000
#: Beams 0..6: NaN, +inf, -inf, range_max, beyond it, below range_min, range_min; what they become.
SPECIAL = [math.nan, math.inf, -math.inf, RANGE_MAX, 35.0, 0.01, RANGE_MIN]
SPECIAL_READ = [math.nan, math.inf, math.nan, math.inf, math.inf, math.nan, float(np.float32(RANGE_MIN))]
BLOB, STATUS = 'acme_msgs/msg/Blob', 'acme_msgs/msg/Status'
CUSTOM = {BLOB: 'uint32 value\nstring name\n', STATUS: 'uint8 level\nstring text\n'}

#: frame -> (parent, translation, (roll, pitch, yaw)): the lasers' mounts on /tf_static.
MOUNTS = {'mount': ('base_link', (0.20, 0.0, 0.30), (0.0, 0.0, 0.5)),
          'laser': ('mount', (0.10, 0.0, 0.05), (0.0, 0.0, 0.25)),
          'rear_laser': ('base_link', (-0.30, 0.05, 0.25), (math.pi, 0.0, math.pi))}


@dataclasses.dataclass
class Item:
    """One message of the scene: topic, type name, bag time (ns) and the message."""

    topic: str
    type_name: str
    time_ns: int
    message: Any


def stamp(t: float) -> Time:
    sec = math.floor(t)
    return Time(sec=T0 + sec, nanosec=round((t - sec) * 1e9))


def quaternion(roll: float, pitch: float, yaw: float) -> Quaternion:
    x, y, z, w = Rotation.from_euler('xyz', [roll, pitch, yaw]).as_quat()
    return Quaternion(x=x, y=y, z=z, w=w)


def ramp() -> np.ndarray:
    """Every beam's range different (so a beam is known by its range), the first seven special."""
    ranges = (1.0 + 0.01 * np.arange(BEAMS)).astype(np.float32)
    ranges[:len(SPECIAL)] = SPECIAL
    return ranges


def scan(t: float, frame: str, *, clockwise: bool = False) -> LaserScan:
    message = LaserScan()
    message.header.stamp, message.header.frame_id = stamp(t), frame
    increment = FOV / (BEAMS - 1)
    message.angle_min, message.angle_max = (FOV / 2, -FOV / 2) if clockwise else (-FOV / 2, FOV / 2)
    message.angle_increment = -increment if clockwise else increment
    message.scan_time, message.range_min, message.range_max = 0.025, RANGE_MIN, RANGE_MAX
    message.ranges = ramp().tolist()
    message.intensities = (np.arange(BEAMS, dtype=np.float32) * 2).tolist()
    return message


def transform(t: float, parent: str, child: str, xyz: Sequence[float], rpy: Sequence[float]) -> TransformStamped:
    message = TransformStamped()
    message.header.stamp, message.header.frame_id, message.child_frame_id = stamp(t), parent, child
    message.transform.translation.x, message.transform.translation.y, message.transform.translation.z = xyz
    message.transform.rotation = quaternion(*rpy)
    return message


def odometry_pose(k: int) -> tuple[float, float, float]:
    return 0.1 * k, 0.01 * k, 0.02 * k


def odometry(t: float, k: int, child: str = 'base_link') -> Odometry:
    message = Odometry()
    message.header.stamp, message.header.frame_id, message.child_frame_id = stamp(t), 'odom', child
    x, y, theta = odometry_pose(k)
    message.pose.pose.position.x, message.pose.pose.position.y = x, y
    message.pose.pose.orientation = quaternion(0.0, 0.0, theta)
    message.twist.twist.linear.x, message.twist.twist.angular.z = 0.5, 0.1
    return message


def imu(t: float, k: int) -> Imu:
    message = Imu()
    message.header.stamp, message.header.frame_id = stamp(t), 'imu_link'
    message.orientation = quaternion(0.0, 0.0, 0.03 * k)
    message.angular_velocity.z, message.linear_acceleration.x = 0.1, 9.81
    return message


def _item(topic: str, type_name: str, t: float, message: Any) -> Item:
    return Item(topic, type_name, T0 * 10**9 + round(t * 1e9) + LATENCY_NS, message)


def full_scene(custom: bool = True) -> list[Item]:
    """Three lasers (one through a chain of mounts, one upside down, one clockwise in the base
    frame), two Odometry topics, an IMU, /tf, and two topics of custom types; the rear laser's
    mount comes on /tf_static after its first scans."""
    items = [_item('/tf_static', 'tf2_msgs/msg/TFMessage', 0.0, TFMessage(transforms=[
        transform(0.0, parent, frame, xyz, rpy) for frame, (parent, xyz, rpy) in MOUNTS.items()
        if frame != 'rear_laser']))]
    parent, xyz, rpy = MOUNTS['rear_laser']
    items.append(_item('/tf_static', 'tf2_msgs/msg/TFMessage', 0.3,
                       TFMessage(transforms=[transform(0.3, parent, 'rear_laser', xyz, rpy)])))
    items += [_item('/scan', 'sensor_msgs/msg/LaserScan', 0.1 + 0.1 * k, scan(0.1 + 0.1 * k, 'laser'))
              for k in range(20)]
    items += [_item('/scan_rear', 'sensor_msgs/msg/LaserScan', 0.15 + 0.2 * k, scan(0.15 + 0.2 * k, '/rear_laser'))
              for k in range(10)]
    items += [_item('/scan_cw', 'sensor_msgs/msg/LaserScan', 0.2 + 0.5 * k,
                    scan(0.2 + 0.5 * k, 'base_link', clockwise=True)) for k in range(5)]
    items += [_item('/odom', 'nav_msgs/msg/Odometry', 0.05 * k, odometry(0.05 * k, k)) for k in range(30)]
    items += [_item('/odometry/filtered', 'nav_msgs/msg/Odometry', 0.05 * k + 0.01, odometry(0.05 * k + 0.01, k))
              for k in range(40)]
    items += [_item('/imu/data', 'sensor_msgs/msg/Imu', 0.1 * k + 0.02, imu(0.1 * k + 0.02, k)) for k in range(15)]
    items += [_item('/tf', 'tf2_msgs/msg/TFMessage', 0.1 * k + 0.03, TFMessage(transforms=[
        transform(0.1 * k + 0.03, 'odom', 'base_link', (*odometry_pose(k)[:2], 0.0), (0.0, 0.0, odometry_pose(k)[2]))]))
        for k in range(10)]
    if custom:
        store = custom_store()
        items += [_item('/acme/blob', BLOB, 0.3 * k, store.types[BLOB](value=k, name='blob')) for k in range(7)]
        items += [_item('/acme/status', STATUS, 0.4 * k, store.types[STATUS](level=1, text='ok')) for k in range(3)]
    return sorted(items, key=lambda i: i.time_ns)


def custom_store() -> Any:
    """The writer's own typestore: ROS 2 Jazzy's types and the two custom ones, known nowhere else."""
    store = get_typestore(Stores.ROS2_JAZZY)
    for name, text in CUSTOM.items():
        store.register(get_types_from_msg(text, name))
    return store


def cdr(item: Item, store: Any) -> bytes:
    """The message's CDR bytes (a message given as bytes is written as it is: damaged data)."""
    if isinstance(item.message, bytes):
        return item.message
    if item.type_name in CUSTOM:
        return bytes(store.serialize_cdr(item.message, item.type_name))
    return serialize_message(item.message)


def write_rosbags(path: pathlib.Path, items: list[Item], *, storage: str = 'sqlite3', compression: str = '',
                  formats: dict[str, str] | None = None, definitions: bool = True) -> pathlib.Path:
    """A bag directory by rosbags' writer.  Blob is written without its definition (as a recorder
    that does not know the type), every type so without ``definitions`` (rosbag2 before Iron);
    ``formats``: topic -> a serialization format other than CDR."""
    store = custom_store()
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    writer = Writer(path, version=9, storage_plugin=plugin)
    if compression:
        writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
    with writer:
        connections = {}
        for item in items:
            if item.topic in connections:
                continue
            undefined = item.type_name == BLOB or not definitions
            extra: dict[str, Any] = {'msgdef': '', 'rihs01': 'RIHS01_' + '0' * 64} if undefined else {}
            connections[item.topic] = writer.add_connection(
                item.topic, item.type_name, typestore=store,
                serialization_format=(formats or {}).get(item.topic, 'cdr'), **extra)
        for item in items:
            writer.write(connections[item.topic], item.time_ns, cdr(item, store))
    return path


def write_split(path: pathlib.Path, items: list[Item], split_ns: int, storage: str = 'sqlite3') -> pathlib.Path:
    """A bag split in two files at ``split_ns`` as rosbag2 splits them (by hand: rosbags does not
    split): both files in one directory, one metadata.yaml naming them in order."""
    parts = [write_rosbags(path.with_name(f'{path.name}-{k}'), part, storage=storage)
             for k, part in enumerate(([i for i in items if i.time_ns < split_ns],
                                       [i for i in items if i.time_ns >= split_ns]))]
    path.mkdir()
    suffix = '.mcap' if storage == 'mcap' else '.db3'
    infos = [yaml.safe_load((part / 'metadata.yaml').read_text())['rosbag2_bagfile_information'] for part in parts]
    for k, part in enumerate(parts):
        shutil.move(part / f'{part.name}{suffix}', path / f'{path.name}_{k}{suffix}')
        shutil.rmtree(part)
    info = infos[0]
    info['relative_file_paths'] = [f'{path.name}_{k}{suffix}' for k in range(len(parts))]
    info['files'] = [{**part['files'][0], 'path': name} for part, name in zip(infos, info['relative_file_paths'])]
    info['message_count'] = sum(part['message_count'] for part in infos)
    end = max(p['starting_time']['nanoseconds_since_epoch'] + p['duration']['nanoseconds'] for p in infos)
    info['duration']['nanoseconds'] = end - info['starting_time']['nanoseconds_since_epoch']
    counts = {t['topic_metadata']['name']: 0 for t in info['topics_with_message_count']}
    for part in infos:
        for topic in part['topics_with_message_count']:
            counts[topic['topic_metadata']['name']] += topic['message_count']
    for topic in info['topics_with_message_count']:
        topic['message_count'] = counts[topic['topic_metadata']['name']]
    (path / 'metadata.yaml').write_text(yaml.safe_dump({'rosbag2_bagfile_information': info}))
    return path


def plain(message: Any) -> Any:
    """An rclpy message as the dicts and lists mcap_ros2 encodes (it takes no numpy arrays)."""
    if hasattr(message, 'get_fields_and_field_types'):
        return {name: plain(getattr(message, name)) for name in message.get_fields_and_field_types()}
    if isinstance(message, (list, tuple, np.ndarray, array.array)):
        return [plain(value) for value in message]
    return message.item() if isinstance(message, np.generic) else message


def write_mcap_ros2(path: pathlib.Path, items: list[Item], chunk_size: int = 1024 * 1024) -> pathlib.Path:
    """One MCAP file by mcap_ros2's writer (it encodes the messages itself, from the definitions)."""
    from mcap_ros2.writer import Writer as McapRos2Writer
    from wurde_mcp.recording.schema import message_definition
    schemas: dict[str, Any] = {}
    with path.open('wb') as stream:
        writer = McapRos2Writer(stream, chunk_size=chunk_size)
        for item in items:
            if item.type_name in CUSTOM:
                continue
            if item.type_name not in schemas:
                schemas[item.type_name] = writer.register_msgdef(item.type_name, message_definition(item.type_name))
            writer.write_message(item.topic, schemas[item.type_name], plain(item.message), log_time=item.time_ns)
        writer.finish()
    return path


def write_record_tool(path: pathlib.Path, items: list[Item]) -> pathlib.Path:
    """One MCAP file as this project's ``record`` writes it (its sink; CDR bytes as they travelled).
    A type the recorder has no definition of gets an empty one (Blob), Status is left out."""
    from mcap.writer import Writer as McapWriter
    from wurde_mcp.recording.record import McapSink
    from wurde_mcp.recording.schema import message_definition
    store = custom_store()
    with path.open('wb') as stream:
        writer = McapWriter(stream)
        writer.start(profile='ros2', library='wurde_mcp record')
        sink = McapSink(writer)
        channels: dict[str, int] = {}
        for item in items:
            if item.type_name == STATUS:
                continue
            if item.topic not in channels:
                definition = '' if item.type_name == BLOB else message_definition(item.type_name)
                channels[item.topic] = sink.open_channel(item.topic, item.type_name, definition, {})
            sink.write(channels[item.topic], cdr(item, store))
        writer.finish()
    return path
