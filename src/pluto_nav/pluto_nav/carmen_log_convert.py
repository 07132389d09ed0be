"""``carmen_log convert LOG OUT.mcap``: a CARMEN log as a ROS 2 bag, standard topics only.

The file is written as rosbag2 writes MCAP (profile ``ros2``; per type a ``ros2msg`` schema with
its full definition; CDR messages; per channel the ``offered_qos_profiles`` YAML and the type's
RIHS01 hash), so that ``ros2 bag info/play``, Foxglove, rosbags' readers and wurde_mcp's ``replay``
read it.  Messages are serialized by rosbags' ROS 2 Jazzy typestore.  The topics are ``/scan``
(and ``/<c>_scan`` for every other laser channel ``c``), ``/odom``, ``/tf``, ``/tf_static`` and
``/truth``; docs/pluto-nav.md ("carmen_log convert") gives each one's type, frames and content.

Each message's log time and header stamp are the record's (the CARMEN line's IPC timestamp).
Besides rosbag2's metadata each channel carries wurde_mcp's ``durability`` and ``reliability``
keys, which its ``replay`` offers again (``/tf_static`` stays latched).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import pathlib
import sys
import tempfile
from collections.abc import Sequence
from typing import Any

import numpy as np
import yaml

from .logs import LogError, LogProblems, OdometryRecord, ScanRecord, TruePoseRecord
from .logs.formats import open_records
from .logs.records import LogRecord, Pose2D
from .logs.robot_log import assemble

__all__ = ['Bag', 'convert', 'main']

SCAN, ODOMETRY, TF = 'sensor_msgs/msg/LaserScan', 'nav_msgs/msg/Odometry', 'tf2_msgs/msg/TFMessage'
#: rmw's "infinite" duration as rosbag2 writes it into offered_qos_profiles.
_INFINITE = {'sec': 9223372036, 'nsec': 854775807}


def offered_qos(*, latched: bool) -> str:
    """The ``offered_qos_profiles`` YAML of one publisher, in rosbag2's (metadata version 9) form."""
    profile = {'history': 'keep_last', 'depth': 1 if latched else 10, 'reliability': 'reliable',
               'durability': 'transient_local' if latched else 'volatile',
               'deadline': dict(_INFINITE), 'lifespan': dict(_INFINITE), 'liveliness': 'automatic',
               'liveliness_lease_duration': dict(_INFINITE), 'avoid_ros_namespace_conventions': False}
    return yaml.safe_dump([profile], default_flow_style=False, sort_keys=False).strip()


def nanoseconds(stamp: float) -> int:
    return int(round(stamp * 1e9))


@dataclasses.dataclass
class Bag:
    """What goes into the file: per topic its type, latching and ``(log time ns, message)``;
    ``store`` is the typestore that serializes them."""

    store: Any = None
    topics: dict[str, tuple[str, bool]] = dataclasses.field(default_factory=dict)
    messages: list[tuple[int, int, str, Any]] = dataclasses.field(default_factory=list)

    def add(self, topic: str, type_name: str, stamp: float, message: Any, *, latched: bool = False) -> None:
        self.topics.setdefault(topic, (type_name, latched))
        self.messages.append((nanoseconds(stamp), len(self.messages), topic, message))


class _Messages:
    """Builders of the rosbags message objects the bag holds."""

    def __init__(self) -> None:
        from rosbags.typesys import Stores, get_typestore
        self.store = get_typestore(Stores.ROS2_JAZZY)
        self.types = self.store.types

    def header(self, stamp: float, frame: str) -> Any:
        ns = nanoseconds(stamp)
        time = self.types['builtin_interfaces/msg/Time'](sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)
        return self.types['std_msgs/msg/Header'](stamp=time, frame_id=frame)

    def pose(self, x: float, y: float, theta: float, z: float = 0.0) -> tuple[Any, Any]:
        point = self.types['geometry_msgs/msg/Point'](x=float(x), y=float(y), z=float(z))
        q = self.types['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2))
        return point, q

    def transform(self, stamp: float, parent: str, child: str, pose: Pose2D) -> Any:
        point, q = self.pose(*pose)
        vector = self.types['geometry_msgs/msg/Vector3'](x=point.x, y=point.y, z=point.z)
        transform = self.types['geometry_msgs/msg/Transform'](translation=vector, rotation=q)
        return self.types['geometry_msgs/msg/TransformStamped'](header=self.header(stamp, parent),
                                                               child_frame_id=child, transform=transform)

    def tf(self, transforms: list[Any]) -> Any:
        return self.types[TF](transforms=transforms)

    def odometry(self, stamp: float, frame: str, pose: Pose2D, tv: float = 0.0, rv: float = 0.0) -> Any:
        t = self.types
        point, q = self.pose(*pose)
        covariance = np.zeros(36, dtype=np.float64)
        with_cov = t['geometry_msgs/msg/PoseWithCovariance'](pose=t['geometry_msgs/msg/Pose'](position=point,
                                                                                          orientation=q),
                                                             covariance=covariance)
        vector = t['geometry_msgs/msg/Vector3']
        twist = t['geometry_msgs/msg/TwistWithCovariance'](
            twist=t['geometry_msgs/msg/Twist'](linear=vector(x=float(tv), y=0.0, z=0.0),
                                               angular=vector(x=0.0, y=0.0, z=float(rv))),
            covariance=covariance.copy())
        return t[ODOMETRY](header=self.header(stamp, frame), child_frame_id='base_link', pose=with_cov, twist=twist)

    def scan(self, record: ScanRecord, frame: str) -> Any:
        config, n = record.config, len(record.ranges)
        intensities = (np.asarray(record.remissions, dtype=np.float32) if record.remissions is not None
                       else np.zeros(0, dtype=np.float32))
        return self.types[SCAN](
            header=self.header(record.stamp, frame), angle_min=float(config.start_angle),
            angle_max=float(config.start_angle + config.angular_resolution * max(n - 1, 0)),
            angle_increment=float(config.angular_resolution), time_increment=0.0, scan_time=0.0,
            range_min=float(config.min_range), range_max=float(config.max_range),
            ranges=np.asarray(record.ranges, dtype=np.float32), intensities=intensities)


def _laser_names(channels: Sequence[str], main: str | None) -> dict[str, tuple[str, str]]:
    """Each channel's topic and frame: the main laser's ``/scan`` in ``laser``, the others'
    ``/<channel>_scan`` in ``<channel>_laser``."""
    return {c: ('/scan', 'laser') if c == main else (f'/{c}_scan', f'{c}_laser') for c in channels}


def collect(path: pathlib.Path, problems: LogProblems) -> Bag:
    """Read the log and build every message of the bag (in memory: a log is small).

    :raises LogError: the log cannot be read at all, or a stamp is negative (MCAP times cannot be).
    """
    records: list[LogRecord] = list(open_records(path, problems))
    log = assemble(str(path), records, problems)
    scans: dict[str, list[ScanRecord]] = {}
    for record in records:
        if isinstance(record, ScanRecord):
            scans.setdefault(record.channel, []).append(record)
    truth = sorted((r for r in records if isinstance(r, TruePoseRecord)), key=lambda r: r.stamp)
    stamps = [r.stamp for r in records if isinstance(r, (ScanRecord, OdometryRecord, TruePoseRecord))]
    if stamps and min(stamps) < 0:
        raise LogError(f'{path}: a negative timestamp ({min(stamps)}): MCAP log times cannot be before 1970')
    build = _Messages()
    bag = Bag(build.store)
    names = _laser_names(sorted(scans), log.scans[0].channel if log.scans else None)
    first = min(stamps) if stamps else 0.0
    statics = [build.transform(first, 'base_link', frame, scans[c][0].config.mount) for c, (_, frame) in names.items()]
    if statics:
        bag.add('/tf_static', TF, first, build.tf(statics), latched=True)
    for channel, (topic, frame) in names.items():
        for scan in sorted(scans[channel], key=lambda s: s.stamp):
            bag.add(topic, SCAN, scan.stamp, build.scan(scan, frame))
    for odom in log.odometry:
        bag.add('/odom', ODOMETRY, odom.stamp, build.odometry(odom.stamp, 'odom', odom.pose, odom.tv, odom.rv))
        bag.add('/tf', TF, odom.stamp, build.tf([build.transform(odom.stamp, 'odom', 'base_link', odom.pose)]))
    for true in truth:
        bag.add('/truth', ODOMETRY, true.stamp, build.odometry(true.stamp, 'map', true.true_pose))
    bag.messages.sort(key=lambda m: (m[0], m[1]))
    return bag


def write(bag: Bag, output: pathlib.Path) -> None:
    """Write ``bag`` to ``output`` (through a temporary file beside it: never half a file).

    :raises OSError: the file cannot be written.
    """
    from mcap.writer import Writer
    store = bag.store
    output.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f'.{output.name}.', dir=output.parent)
    try:
        with os.fdopen(handle, 'wb') as stream:
            writer = Writer(stream)
            writer.start(profile='ros2', library='pluto_nav carmen_log')
            schemas: dict[str, int] = {}
            channels: dict[str, int] = {}
            for topic, (type_name, latched) in bag.topics.items():
                if type_name not in schemas:
                    definition = store.generate_msgdef(type_name, ros_version=2)[0]
                    schemas[type_name] = writer.register_schema(type_name, 'ros2msg', definition.encode())
                metadata = {'offered_qos_profiles': offered_qos(latched=latched),
                            'topic_type_hash': store.hash_rihs01(type_name),
                            'durability': 'transient_local' if latched else 'volatile',
                            'reliability': 'reliable'}
                channels[topic] = writer.register_channel(topic, 'cdr', schemas[type_name], metadata)
            counts: dict[str, int] = {}
            for ns, _, topic, message in bag.messages:
                data = bytes(store.serialize_cdr(message, bag.topics[topic][0]))
                writer.add_message(channels[topic], log_time=ns, publish_time=ns, data=data,
                                   sequence=counts.get(topic, 0))
                counts[topic] = counts.get(topic, 0) + 1
            writer.finish()
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)   # as an ordinary new file (mkstemp's is private)
        os.replace(temporary, output)
    except BaseException:
        pathlib.Path(temporary).unlink(missing_ok=True)
        raise


def convert(log: pathlib.Path, output: pathlib.Path, problems: LogProblems) -> dict[str, int]:
    """Convert ``log`` to ``output``; returns the number of messages per topic.

    :raises LogError: the log cannot be read.  :raises OSError: the output cannot be written.
    """
    bag = collect(log, problems)
    write(bag, output)
    counts: dict[str, int] = {}
    for _, _, topic, _ in bag.messages:
        counts[topic] = counts.get(topic, 0) + 1
    return counts


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    parser = argparse.ArgumentParser(prog=argv[0] if argv else 'carmen_log convert',
                                     description=(__doc__ or '').split('\n\n')[0])
    parser.add_argument('log', help='a CARMEN log (plain or gzip)')
    parser.add_argument('output', help='the MCAP file to write (OUT.mcap)')
    args = parser.parse_args(argv[1:])
    name = pathlib.Path(argv[0]).name.split()[0] if argv else 'carmen_log'
    problems = LogProblems(lambda text: print(f'{name}: {text}', file=sys.stderr, flush=True))
    try:
        counts = convert(pathlib.Path(args.log), pathlib.Path(args.output), problems)
    except LogError as error:
        print(f'{name}: {error}', file=sys.stderr, flush=True)
        return 2
    except OSError as error:
        print(f'{name}: cannot write {args.output}: {error.strerror or error}', file=sys.stderr, flush=True)
        return 1
    topics = ', '.join(f'{n} on {t}' for t, n in sorted(counts.items()))
    print(f'{name}: wrote {args.output}: {topics or "no messages"} ({problems.summary()})', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
