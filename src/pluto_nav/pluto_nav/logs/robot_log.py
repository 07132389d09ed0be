"""A whole recording in memory, as the offline tools use it: the scans of one laser, the odometry,
the truth and the parameters, each in time order, and what was wrong with the file.

:func:`load_log` chooses the reader by the file's content (a CARMEN log, plain or gzip; a rosbag2
bag: its directory, its ``metadata.yaml``, or one ``.mcap`` / ``.db3`` file).  Where the odometry
comes from (the real-data issue's rule, after CARMEN's own logs): a log's odometry records (CARMEN's
``ODOM`` lines, a bag's ``nav_msgs/Odometry``) when it has any; otherwise, in old raw CARMEN logs,
the odometry fields the laser lines carry.
"""

from __future__ import annotations

import bisect
import dataclasses
import pathlib
from collections.abc import Callable, Iterable

from ..geometry import compose, relative
from .problems import LogError, LogProblems
from .records import (ImuRecord, LogRecord, OdometryRecord, ParamRecord, Pose2D, ScanRecord,
                      TruePoseRecord)

__all__ = ['RobotLog', 'load_log']


@dataclasses.dataclass
class RobotLog:
    """One recording: every list in time order.

    :ivar scans: the chosen laser's scans.
    :ivar odometry: the odometry, from odometry records or, without any, from the scans' own
        odometry fields (:attr:`odometry_source` says which).
    :ivar lasers: every laser channel the file has, with its number of scans.
    """

    path: str
    scans: list[ScanRecord]
    odometry: list[OdometryRecord]
    odometry_source: str
    true_poses: list[TruePoseRecord]
    imu: list[ImuRecord]
    params: dict[str, str]
    lasers: dict[str, int]
    problems: LogProblems

    @property
    def start(self) -> float:
        stamps = [r[0].stamp for r in (self.scans, self.odometry) if r]
        return min(stamps) if stamps else 0.0

    @property
    def end(self) -> float:
        stamps = [r[-1].stamp for r in (self.scans, self.odometry) if r]
        return max(stamps) if stamps else 0.0

    @property
    def duration(self) -> float:
        return self.end - self.start

    def odometry_at(self, stamp: float) -> Pose2D | None:
        """The odometry pose at ``stamp``, interpolated along the increment between the samples around it.

        :param stamp: seconds, on the recording's clock (the records' stamps).
        :returns: ``(x, y, theta)`` in the odometry frame; None before the first or after the last sample.
        """
        stamps = self._stamps()
        i = bisect.bisect_left(stamps, stamp)
        if i < len(stamps) and stamps[i] == stamp:
            return self.odometry[i].pose
        if i == 0 or i == len(stamps):
            return None
        a, b = self.odometry[i - 1], self.odometry[i]
        f = (stamp - a.stamp) / (b.stamp - a.stamp)
        dx, dy, dtheta = relative(a.pose, b.pose)
        x, y, theta = compose(a.pose, (f * dx, f * dy, f * dtheta))
        return float(x), float(y), float(theta)

    def _stamps(self) -> list[float]:
        if getattr(self, '_stamp_cache', None) is None or len(self._stamp_cache) != len(self.odometry):
            self._stamp_cache: list[float] = [r.stamp for r in self.odometry]
        return self._stamp_cache


def _choose_laser(scans: dict[str, list[ScanRecord]], laser: str | None) -> str | None:
    if laser is not None:
        return laser
    for preferred in ('front', 'raw1'):
        if scans.get(preferred):
            return preferred
    return max(scans, key=lambda c: len(scans[c]), default=None)


def assemble(path: str, records: Iterable[LogRecord], problems: LogProblems, *,
             laser: str | None = None) -> RobotLog:
    """Sort ``records`` into a :class:`RobotLog` (see the module's description for the odometry).

    :param path: the recording's name, for the log and messages.
    :param records: the records a reader yields, in any order.
    :param problems: where problems go; a laser asked for and missing is reported there as an error.
    :param laser: which laser channel's scans to keep (as :func:`load_log`); None: the front laser,
        else ``raw1``, else the one with most scans.
    """
    scans: dict[str, list[ScanRecord]] = {}
    odometry: list[OdometryRecord] = []
    truth: list[TruePoseRecord] = []
    imu: list[ImuRecord] = []
    params: dict[str, str] = {}
    for record in records:
        if isinstance(record, ScanRecord):
            scans.setdefault(record.channel, []).append(record)
        elif isinstance(record, OdometryRecord):
            odometry.append(record)
        elif isinstance(record, TruePoseRecord):
            truth.append(record)
        elif isinstance(record, ImuRecord):
            imu.append(record)
        elif isinstance(record, ParamRecord):
            params[record.name] = record.value
    channel = _choose_laser(scans, laser)
    if laser is not None and laser not in scans:
        problems.error(f'{path}: no scans of the laser {laser!r} (it has {sorted(scans) or "none"})')
    chosen = sorted(scans.get(channel, []) if channel else [], key=lambda s: s.stamp)
    source = 'odometry records'
    if not odometry:
        odometry = [OdometryRecord(s.stamp, *s.odometry, origin=s.origin) for s in chosen
                    if s.odometry is not None]
        source = 'the laser lines' if odometry else 'none'
    for items in (odometry, truth, imu):
        items.sort(key=lambda r: r.stamp)
    return RobotLog(path, chosen, odometry, source, truth, imu, params,
                    {c: len(s) for c, s in scans.items()}, problems)


def load_log(path: str | pathlib.Path, *, laser: str | None = None,
             warn: Callable[[str], None] | None = None) -> RobotLog:
    """Read a CARMEN log or a rosbag2 bag (chosen by content) into a :class:`RobotLog`.

    :param path: a CARMEN log (plain or gzip), or a rosbag2 bag: its directory, its
        ``metadata.yaml`` or one ``.mcap`` / ``.db3`` file.
    :param laser: which laser's scans (a channel name, e.g. ``front``, ``rear``, ``raw1`` or a bag's
        topic); by default the front laser, else the laser with most scans.
    :param warn: where warnings go (one per kind of problem; default: standard error).
    :raises pluto_nav.logs.problems.LogError: a file that cannot be read at all (missing, neither a
        CARMEN log nor a bag, nothing usable in it).
    """
    from .formats import open_records   # the readers import what they need only when used
    problems = LogProblems(warn)
    records = open_records(pathlib.Path(path), problems)
    log = assemble(str(path), records, problems, laser=laser)
    if not log.lasers and not log.odometry:
        raise LogError(f'{path}: no usable record: no laser scan and no odometry ({problems.summary()})')
    return log
