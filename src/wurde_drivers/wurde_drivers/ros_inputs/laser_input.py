"""The robot's LaserScan in, the laser streams out: ``<LASER>``, ``<LASER>/RWI``, ``<LASER>/Timing``.

Each scan goes through :func:`~.scan.to_robot` (the suite's order, ``inf`` and NaN, the centre
stamp) and out through the same :class:`~wurde_drivers.streams.laser.LaserStreams` as the SICK
driver and the dummy laser, with a :class:`~wurde_drivers.streams.laser.Fan` for its beams:
``<LASER>`` and ``<LASER>/Timing`` stamped at the scan's centre, ``<LASER>/RWI`` (the same beams)
at its end.

**The mount.**  Where the laser sits comes from the robot's transforms (:mod:`.frames`: the
chain base frame → laser frame, from ``/tf_static`` and ``/tf``).  The RangeFinder info (mount
x/y/z, the fan's first bearing and step, ``max_range``) is published once the mount is known and
again whenever it or the scan's fan changes.  Scans that come before the mount is known are
**held**, the newest ``max_held_scans`` of them, and published in order once it is known (the
localModule places a scan by its stamp, so a late scan is not a wrong one); older ones are dropped
and counted, and the count is logged when the mount is found.
"""

from __future__ import annotations

import collections
import math
import time
from collections.abc import Callable
from typing import Any

from wurde_core import Logger

from ..ros_std_frames import frame_of
from ..streams.laser import Fan, LaserStreams
from .frames import FrameTree, Mount, Transform, mount_of
from .robot_topics import RobotTopics, seconds
from .scan import RobotScan, to_robot
from .settings import Settings
from .topic_watch import TopicWatch

__all__ = ['LaserInput']

#: A laser tilted more than this (rad) from level is said to be (its fan is taken as level).
TILT_WARNING = math.radians(5.0)
#: Seconds of held scans after which the frames known are listed (once).
HOLD_WARNING_S = 5.0


class LaserInput:
    """Scans and transforms → the laser streams; :meth:`step` every loop turn."""

    def __init__(self, name: str, settings: Settings, topics: RobotTopics, logger: Logger) -> None:
        self.settings, self.topics, self.logger = settings, topics, logger
        self.streams = LaserStreams(name)
        self.tree = FrameTree()
        self.watch = TopicWatch(f'LaserScan on {topics.scan_topic}', settings.silent_after,
                                self._warn, lambda: topics.publishers(topics.scan_topic))
        self.mount: Mount | None = None
        self.held: collections.deque[Any] = collections.deque()
        self.dropped = 0
        self.refused = 0
        self.published = 0
        self._frames: tuple[str, str] | None = None      # (base, laser) the mount is of
        self._announced: tuple[float, ...] | None = None
        self._holding_since: float | None = None
        self._told: set[str] = set()
        self._own_frame = frame_of(name)
        self._tree_changed = False

    def _warn(self, text: str) -> None:
        self.logger.warn(f'{self.streams.name}: {text}')

    def _once(self, key: str, text: str) -> None:
        if key not in self._told:
            self._told.add(key)
            self._warn(text)

    # -- transforms -----------------------------------------------------------------------------
    def take_transforms(self) -> bool:
        """Put every transform that arrived into the tree; whether any did."""
        changed = False
        for message, _static in self.topics.transforms():
            parent, child = message.header.frame_id, message.child_frame_id
            if child.lstrip('/') == self._own_frame:
                continue          # our own mirror frame (LaserStreams' /tf_static): not the robot's
            t, r = message.transform.translation, message.transform.rotation
            try:
                transform = Transform.from_values((t.x, t.y, t.z), (r.x, r.y, r.z, r.w))
            except ValueError as error:
                self._once(f'tf {parent} {child}', f'transform {parent} -> {child} left out: {error}')
                continue
            self.tree.set(parent, child, transform)
            changed = True
        return changed

    def _find_mount(self, base: str, laser: str) -> None:
        if laser == base:
            transform: Transform | None = Transform.identity()
        else:
            transform = self.tree.lookup(base, laser)
        if transform is None:
            return
        mount = mount_of(transform)
        if mount.close_to(self.mount) and self._frames == (base, laser):
            return
        self.mount, self._frames = mount, (base, laser)
        self.logger.notice(f'{self.streams.name}: laser frame "{laser}" in "{base}": x {mount.x:.3f} '
                           f'y {mount.y:.3f} z {mount.z:.3f} m, yaw {math.degrees(mount.yaw):.1f} deg'
                           f'{", upside down" if mount.upside_down else ""}')
        if mount.tilt > TILT_WARNING:
            self._once('tilt', f'the laser is tilted {math.degrees(mount.tilt):.1f} deg from level: '
                       'its beams are taken as level')

    # -- scans ----------------------------------------------------------------------------------
    def step(self, base_frame: str, now: Callable[[], float]) -> int:
        """Take transforms and scans, publish what can be; returns the scans published."""
        self._tree_changed |= self.take_transforms()
        for message in self.topics.scans():
            self.watch.heard()
            self.held.append(message)
        if not self.held:
            return 0
        laser = self.settings.laser_frame or self.held[-1].header.frame_id.lstrip('/')
        if not laser:
            self._once('frame', f'scans on {self.topics.scan_topic} name no frame_id: the laser is '
                       'taken to sit at the base frame (set the parameter laser_frame)')
            laser = base_frame
        if base_frame and (self._tree_changed or self.mount is None or self._frames != (base_frame, laser)):
            self._tree_changed = False
            self._find_mount(base_frame, laser)
        if self.mount is None or self._frames != (base_frame, laser):
            self._hold(base_frame, laser)
            return 0
        if self._holding_since is not None:
            self._holding_since = None
            self.logger.notice(f'{self.streams.name}: mount known: publishing {len(self.held)} held '
                               f'scans ({self.dropped} dropped while waiting)')
        count = 0
        while self.held:
            count += self._publish(self.held.popleft(), now)
        return count

    def _hold(self, base: str, laser: str) -> None:
        while len(self.held) > self.settings.max_held_scans:
            self.held.popleft()
            self.dropped += 1
        why = (f'the mount of laser frame "{laser}" in "{base}" is not known yet' if base else
               'the base frame is not known yet (no Odometry with a child_frame_id; or set the '
               'parameter base_frame)')
        now = time.monotonic()
        if self._holding_since is None:
            self._holding_since = now
            self.logger.notice(f'{self.streams.name}: {why}: holding the newest '
                               f'{self.settings.max_held_scans} scans, dropping older ones')
        elif now - self._holding_since > HOLD_WARNING_S:
            self._once('hold', f'{why} after {HOLD_WARNING_S:g} s; frames known: '
                       f'{", ".join(self.tree.frames()) or "none"}')

    def _publish(self, message: Any, now: Callable[[], float]) -> int:
        assert self.mount is not None
        stamp = seconds(message.header.stamp)
        if stamp == 0.0:
            self._once('stamp', f'scans on {self.topics.scan_topic} have no stamp: stamped on arrival')
            stamp = now()
        try:
            scan = to_robot(message.ranges, angle_min=message.angle_min,
                            angle_increment=message.angle_increment, range_min=message.range_min,
                            range_max=message.range_max, stamp=stamp,
                            time_increment=message.time_increment, mount=self.mount)
        except ValueError as error:
            self.refused += 1
            self._once('refused', f'scan on {self.topics.scan_topic} refused: {error} (further '
                       'refusals are counted, not logged)')
            return 0
        self._announce(scan, message)
        self.streams.publish_scan(scan.ranges.tolist(), centre_stamp=scan.centre, arrival_stamp=scan.end)
        self.published += 1
        if self.published == 1:
            self.logger.notice(f'{self.streams.name}: first scan: {len(scan.ranges)} beams from '
                               f'{math.degrees(scan.first):.1f} deg every '
                               f'{math.degrees(scan.step):.3f} deg (robot frame)')
        return 1

    def _announce(self, scan: RobotScan, message: Any) -> None:
        """Publish the info when the fan or the mount differs from the one announced."""
        mount = self.mount
        assert mount is not None
        key = (float(len(scan.ranges)), round(scan.first, 6), round(scan.step, 9), scan.max_range,
               round(mount.x, 4), round(mount.y, 4), round(mount.z, 4))
        if key == self._announced:
            return
        self._announced = key
        scan_time = float(message.scan_time) if math.isfinite(message.scan_time) else 0.0
        between = abs(float(message.time_increment)) if math.isfinite(message.time_increment) else 0.0
        self.streams.publish_info(count=len(scan.ranges), max_range=scan.max_range, mount_x=mount.x,
                                  mount_y=mount.y, mount_z=mount.z, scan_time=max(scan_time, 0.0),
                                  fan=Fan(scan.first, scan.step, between))
