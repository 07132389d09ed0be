"""rosbag2 bags of any ROS 2 robot as records: the scans, the odometry and the IMU, without ROS.

- every ``sensor_msgs/msg/LaserScan`` topic: :class:`ScanRecord` (``channel`` = the topic's name),
  the laser's mount from TF (the base frame -> ... -> the scan's ``frame_id``);
- one ``nav_msgs/msg/Odometry`` topic (``/odom``, else the one with most messages; a note says
  which when there is a choice): :class:`OdometryRecord`; its ``child_frame_id`` is the base frame;
- without Odometry, the ``/tf`` transforms from the odometry frame (``odom``) to the base frame:
  :class:`OdometryRecord` (speeds from consecutive poses);
- one ``sensor_msgs/msg/Imu`` topic (``/imu/data``, ``/imu``, else most): :class:`ImuRecord`.

Stamps are the messages' ``header.stamp`` (the bag's receive time where a driver left it zero);
records come out in stamp order (within :data:`ORDER_HORIZON`).  Ranges follow
:class:`~.records.ScanRecord`: +inf and ``>= range_max`` become inf (nothing seen); NaN (an
erroneous or missing reading), ``< range_min`` and -inf (too close) stay or become NaN (no
reading), after REP-117; scans that turn clockwise or come
from a laser mounted upside down are reversed into counter-clockwise order (:mod:`.bag_frames`).

Two passes: the first reads ``/tf_static``, the first scan of each laser and, until every laser's
frame is joined to the base, ``/tf`` (usually its first messages); the second reads the rest.
Problems (a type no one can read, a message that does not decode, a laser frame with no transform
to the base, stamps going back) are counted in the :class:`~.problems.LogProblems`, one warning each.
"""

from __future__ import annotations

import collections
import heapq
import math
import pathlib
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np
from rosbags.interfaces import Connection

from ..geometry import relative
from .bag_frames import (TILT_NOTICE, FrameTree, PlanarMount, frame_name, laser_geometry, planar_mount,
                         transform_matrix)
from .bag_storage import Bag, bag_typestore, open_bag
from .problems import LogError, LogProblems
from .records import ImuRecord, LaserConfig, LogRecord, OdometryRecord, ScanRecord

__all__ = ['read_rosbag']

SCAN, ODOMETRY, IMU, TF = ('sensor_msgs/msg/LaserScan', 'nav_msgs/msg/Odometry', 'sensor_msgs/msg/Imu',
                           'tf2_msgs/msg/TFMessage')
ODOMETRY_TOPICS = ('/odom',)
IMU_TOPICS = ('/imu/data', '/imu')
#: The base frame when the bag tells none (no Odometry, no odom -> base transform).
BASE_FRAMES = ('base_link', 'base_footprint')
#: s: records are held this long (in stamp time) to be given out in stamp order ...
ORDER_HORIZON = 1.0
#: ... but never more than this many at once.
ORDER_CAP = 20000


def read_rosbag(path: pathlib.Path, problems: LogProblems) -> Iterator[LogRecord]:
    """Every scan, odometry and IMU record of the bag at ``path``, in stamp order.

    :param path: a bag directory, its ``metadata.yaml`` or one ``.mcap`` / ``.db3`` file.
    :param problems: where skipped topics and messages are reported.
    :raises LogError: not a readable bag, a serialization other than CDR, no messages, no LaserScan.
    """
    with open_bag(path, problems) as bag:
        yield from _BagReading(bag, problems).records()


def _seconds(stamp: Any) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def _yaw(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _odometry_frame(frame: str) -> bool:
    return frame == 'odom' or frame.endswith(('/odom', '_odom'))


class _TimeOrder:
    """Records held in a heap until nothing earlier can come (within the horizon)."""

    def __init__(self) -> None:
        self._heap: list[tuple[float, int, LogRecord]] = []
        self._count = 0
        self._newest = -math.inf

    def push(self, record: LogRecord) -> Iterator[LogRecord]:
        heapq.heappush(self._heap, (record.stamp, self._count, record))
        self._count += 1
        self._newest = max(self._newest, record.stamp)
        while self._heap and (self._heap[0][0] <= self._newest - ORDER_HORIZON or len(self._heap) > ORDER_CAP):
            yield heapq.heappop(self._heap)[2]

    def flush(self) -> Iterator[LogRecord]:
        while self._heap:
            yield heapq.heappop(self._heap)[2]


class _BagReading:
    """One reading of one bag: which topics, the frames, and the records."""

    def __init__(self, bag: Bag, problems: LogProblems) -> None:
        self.bag = bag
        self.problems = problems
        self.store, unreadable = bag_typestore(bag.connections)
        self._report_unreadable(unreadable)
        readable = [c for c in bag.connections if c.msgtype not in unreadable]
        self.scans = [c for c in readable if c.msgtype == SCAN]
        self.tf_static = [c for c in readable if c.msgtype == TF and c.topic.endswith('tf_static')]
        self.tf = [c for c in readable if c.msgtype == TF and not c.topic.endswith('tf_static')]
        odometry = self._choose([c for c in readable if c.msgtype == ODOMETRY], ODOMETRY_TOPICS, 'odometry')
        imu = self._choose([c for c in readable if c.msgtype == IMU], IMU_TOPICS, 'IMU')
        self.odometry = [c for c in readable if c.msgtype == ODOMETRY and c.topic == odometry]
        self.imu = [c for c in readable if c.msgtype == IMU and c.topic == imu]
        self.frames = FrameTree()
        self.base: str | None = None
        self.odom_frame: str | None = None
        self._mounts: dict[str, tuple[PlanarMount, set[str]] | None] = {}
        self._configs: dict[tuple, tuple[LaserConfig, bool]] = {}
        self._last_stamp: dict[str, float] = {}
        self._last_tf_odometry: OdometryRecord | None = None

    def where(self, topic: str) -> str:
        return f'{self.bag.name}:{topic}'

    # -- which topics -------------------------------------------------------------------------------

    def _report_unreadable(self, unreadable: dict[str, str]) -> None:
        for msgtype, why in sorted(unreadable.items()):
            connections = [c for c in self.bag.connections if c.msgtype == msgtype]
            topics = sorted({c.topic for c in connections})
            also = f' (also on {", ".join(topics[1:])})' if len(topics) > 1 else ''
            for _ in range(sum(c.msgcount for c in connections)):
                self.problems.skip(f'message of the type {msgtype or "(none)"} that cannot be read',
                                   self.where(topics[0]), f'{why}{also}')

    def _choose(self, connections: list[Connection], preferred: tuple[str, ...], what: str) -> str | None:
        counts: collections.Counter[str] = collections.Counter()
        for connection in connections:
            counts[connection.topic] += connection.msgcount
        topics = sorted(t for t in counts if counts[t]) or sorted(counts)
        if not topics:
            return None
        chosen = next((t for t in preferred if t in topics), None) or max(topics, key=lambda t: counts[t])
        if len(topics) > 1:
            self.problems.note(f'{what} topic chosen', self.bag.name,
                               f'{chosen} of {", ".join(f"{t} ({counts[t]})" for t in topics)}')
        return chosen

    def _check_scans(self) -> None:
        if not any(c.msgcount for c in self.bag.connections):
            raise LogError(f'{self.bag.name}: an empty bag (no messages)')
        if not any(c.msgcount for c in self.scans):
            counts: collections.Counter[tuple[str, str]] = collections.Counter()
            for connection in self.bag.connections:
                counts[connection.topic, connection.msgtype] += connection.msgcount
            present = [f'{topic} ({msgtype}, {n})' for (topic, msgtype), n in sorted(counts.items())]
            shown = ', '.join(present[:12]) + (f' and {len(present) - 12} more' if len(present) > 12 else '')
            raise LogError(f'{self.bag.name}: no {SCAN} messages (a log needs laser scans); '
                           f'it has (topic, type, messages): {shown}')

    # -- decoding and frames -------------------------------------------------------------------------

    def _decode(self, connection: Connection, raw: bytes, count: bool = True) -> Any:
        try:
            return self.store.deserialize_cdr(raw, connection.msgtype)
        except Exception as error:   # noqa: BLE001 -- bytes from the file: any decoding error
            if count:
                self.problems.skip(f'{connection.msgtype} message that cannot be decoded',
                                   self.where(connection.topic), f'{type(error).__name__}: {error}')
            return None

    def _apply_tf(self, connection: Connection, message: Any, changed: set[str],
                  count: bool = True) -> list[OdometryRecord]:
        """Put a TF message's transforms in the tree (``changed`` gets their child frames); the
        odometry they give when the bag has no Odometry.  ``count``: problems are counted (not in
        the first pass over /tf, which the second reads again)."""
        made = []
        static = connection.topic.endswith('tf_static')
        for transform in message.transforms:
            parent, child = frame_name(transform.header.frame_id), frame_name(transform.child_frame_id)
            t, q = transform.transform.translation, transform.transform.rotation
            matrix = transform_matrix((t.x, t.y, t.z), (q.x, q.y, q.z, q.w))
            if matrix is None:
                if count:
                    self.problems.skip('transform with an invalid rotation', self.where(connection.topic),
                                       f'{parent} -> {child}: quaternion ({q.x}, {q.y}, {q.z}, {q.w})')
                continue
            self.frames.set(parent, child, matrix)
            changed.add(child)
            if self.odometry or static:
                continue
            if self.base is None and _odometry_frame(parent):
                self.base, self.odom_frame = child, parent
                self.problems.note('odometry from /tf', self.bag.name,
                                   f'no {ODOMETRY} topic: the transforms {parent} -> {child} are the odometry')
            if (parent, child) == (self.odom_frame, self.base):
                made.append(self._tf_odometry(connection, transform, (t.x, t.y, _yaw(q))))
        return made

    def _tf_odometry(self, connection: Connection, transform: Any, pose: tuple[float, float, float]) -> OdometryRecord:
        stamp = _seconds(transform.header.stamp)
        tv = rv = 0.0
        last = self._last_tf_odometry
        if last is not None and stamp > last.stamp:
            dx, _, dtheta = relative(last.pose, pose)
            tv, rv = float(dx) / (stamp - last.stamp), float(dtheta) / (stamp - last.stamp)
        record = OdometryRecord(stamp, *pose, tv=tv, rv=rv, origin=self.where(connection.topic))
        self._last_tf_odometry = record
        return record

    def _mount(self, frame: str) -> PlanarMount | None:
        if frame not in self._mounts:
            found = self.frames.lookup(self.base or BASE_FRAMES[0], frame)
            self._mounts[frame] = (planar_mount(found[0]), found[1]) if found else None
        entry = self._mounts[frame]
        return entry[0] if entry else None

    def _forget_mounts(self, changed: Iterable[str]) -> None:
        changed = set(changed)
        for frame, entry in list(self._mounts.items()):
            if entry is None or entry[1] & changed:
                del self._mounts[frame]

    # -- the two passes ------------------------------------------------------------------------------

    def records(self) -> Iterator[LogRecord]:
        self._check_scans()
        self._prepare()
        order = _TimeOrder()
        for record in self._main():
            yield from order.push(record)
        yield from order.flush()

    def _prepare(self) -> None:
        """Pass 1: /tf_static, the base frame, each laser's frame and /tf until they are joined."""
        changed: set[str] = set()
        for connection, _, raw in self.bag.messages(self.tf_static):
            if (message := self._decode(connection, raw)) is not None:
                self._apply_tf(connection, message, changed)
        lasers: dict[str, str] = {}
        waiting = {c.topic for c in self.scans if c.msgcount}
        for connection, _, raw in self.bag.messages(self.scans + self.odometry + self.tf):
            news = False
            if connection.msgtype == SCAN and connection.topic in waiting:
                if (message := self._decode(connection, raw, count=False)) is not None:
                    lasers[connection.topic] = frame_name(message.header.frame_id)
                    waiting.discard(connection.topic)
                    news = True
            elif connection.msgtype == ODOMETRY and self.base is None:
                if (message := self._decode(connection, raw, count=False)) is not None:
                    self.base = frame_name(message.child_frame_id) or BASE_FRAMES[0]
                    news = True
            elif connection.msgtype == TF:
                if (message := self._decode(connection, raw, count=False)) is not None:
                    before = len(changed)
                    self._apply_tf(connection, message, changed, count=False)
                    news = len(changed) > before
            if news and self.base is not None and not waiting:
                self._mounts.clear()
                if all(self._mount(frame) is not None for frame in lasers.values()):
                    break
        if self.base is None:
            self.base = next((f for f in BASE_FRAMES if f in self.frames), BASE_FRAMES[0])
            self.problems.note('base frame assumed', self.bag.name,
                               f'no {ODOMETRY} and no odom -> base transform: the base frame is {self.base}')
        self._mounts.clear()
        self._last_tf_odometry = None

    def _main(self) -> Iterator[LogRecord]:
        """Pass 2: every record."""
        for connection, bag_time, raw in self.bag.messages(self.scans + self.odometry + self.imu + self.tf):
            message = self._decode(connection, raw)
            if message is None:
                continue
            if connection.msgtype == TF:
                changed: set[str] = set()
                made = self._apply_tf(connection, message, changed)
                self._forget_mounts(changed)
                for odometry in made:
                    self._in_order(connection.topic, odometry.stamp)
                    yield odometry
                continue
            stamp = self._stamp(connection.topic, message.header.stamp, bag_time)
            record: LogRecord | None
            if connection.msgtype == SCAN:
                record = self._scan(connection, message, stamp)
            elif connection.msgtype == ODOMETRY:
                pose, twist = message.pose.pose, message.twist.twist
                record = OdometryRecord(stamp, pose.position.x, pose.position.y, _yaw(pose.orientation),
                                        tv=twist.linear.x, rv=twist.angular.z,
                                        origin=self.where(connection.topic))
            else:
                record = self._imu(connection, message, stamp)
            if record is not None:
                yield record

    def _stamp(self, topic: str, stamp: Any, bag_time: int) -> float:
        seconds = _seconds(stamp)
        if seconds == 0.0:
            self.problems.note('message without a header stamp', self.where(topic),
                               'the bag\'s receive time is used')
            seconds = bag_time * 1e-9
        self._in_order(topic, seconds)
        return seconds

    def _in_order(self, topic: str, stamp: float) -> None:
        last = self._last_stamp.get(topic)
        if last is not None and stamp < last:
            self.problems.note(f'stamp going back on {topic}', self.where(topic),
                               f'{stamp:.6f} s after {last:.6f} s (records are sorted by stamp)')
        self._last_stamp[topic] = stamp

    # -- messages to records -------------------------------------------------------------------------

    def _scan(self, connection: Connection, message: Any, stamp: float) -> ScanRecord | None:
        topic, frame = connection.topic, frame_name(message.header.frame_id)
        mount = self._mount(frame)
        if mount is None:
            self.problems.skip(f'{topic} scan with no transform to the base', self.where(topic),
                               f'no chain of /tf_static or /tf transforms from {self.base!r} to the laser\'s '
                               f'frame {frame!r}')
            return None
        if mount.tilt > TILT_NOTICE:
            self.problems.note(f'{topic} laser tilted', self.where(topic),
                               f'its plane leans {math.degrees(mount.tilt):.0f} degrees from {self.base}\'s: '
                               f'projected on it')
        ranges = np.asarray(message.ranges, dtype=np.float64)
        range_min, range_max = float(message.range_min), float(message.range_max)
        if not (math.isfinite(range_min) and range_min >= 0.0):
            range_min = 0.0
        if not (math.isfinite(range_max) and range_max > range_min):
            self.problems.note(f'{topic} range_max unusable', self.where(topic),
                               f'range_max {message.range_max}: only inf and NaN readings taken as nothing seen')
            range_max = math.inf
        key = (float(message.angle_min), float(message.angle_increment), len(ranges), range_min, range_max,
               id(mount))
        if key not in self._configs:
            self._configs[key] = laser_geometry(key[0], key[1], len(ranges), range_min, range_max, mount)
        config, reverse = self._configs[key]
        values = ranges.copy()
        with np.errstate(invalid='ignore'):
            values[(ranges >= range_max) | np.isposinf(ranges)] = math.inf
            values[(ranges < range_min) | np.isneginf(ranges)] = math.nan
        remissions = None
        if len(message.intensities) == len(ranges) and len(ranges):
            remissions = np.asarray(message.intensities, dtype=np.float64)
        if reverse:
            values = values[::-1].copy()
            remissions = remissions[::-1].copy() if remissions is not None else None
        return ScanRecord(stamp, values, config, channel=topic, remissions=remissions, origin=self.where(topic))

    def _imu(self, connection: Connection, message: Any, stamp: float) -> ImuRecord:
        q, w, a = message.orientation, message.angular_velocity, message.linear_acceleration
        known = message.orientation_covariance[0] != -1.0 and (q.x, q.y, q.z, q.w) != (0.0, 0.0, 0.0, 0.0)
        return ImuRecord(stamp, (q.x, q.y, q.z, q.w) if known else None, (w.x, w.y, w.z), (a.x, a.y, a.z),
                         origin=self.where(connection.topic))
