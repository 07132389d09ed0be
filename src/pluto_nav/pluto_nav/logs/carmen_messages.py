"""CARMEN's log messages, one line each, into records: the field layouts and CARMEN's conventions.

Each parser takes a line's whitespace-separated fields (the message name first) and where the line
is (``file:line``), and returns one record or raises :class:`LineError` saying what kind of problem
the line has.  The layouts are those CARMEN's logger writes and its reader parses
(``src/logtools/writelog.c`` ``carmen_logwrite_write_*`` and ``readlog.c``
``carmen_string_to_*``; the old-format lines as ``src/logger/playback.c`` reads them).  Every
message ends with ``timestamp hostname logger_timestamp``: the IPC time the reading was taken (our
``stamp``), the host, and the logger's own clock (checked, not kept).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..geometry import compose, relative
from .records import LaserConfig, OdometryRecord, ParamRecord, Pose2D, ScanRecord, TruePoseRecord

__all__ = ['LineError', 'Mounts', 'guess_angle_increment', 'guess_fov', 'parse_line', 'PARSERS']

#: CARMEN's guess for the old-format lines that carry no laser configuration (readlog.c,
#: ``carmen_string_to_robot_laser_message_orig``): a SICK LMS, first beam at -90 degrees, 80 m.
OLD_START_ANGLE = -math.pi / 2.0
OLD_MAX_RANGE = 80.0
_TAIL = 3          # timestamp hostname logger_timestamp
_SAME_POSE = 1e-4  # m and rad: laser and robot pose closer than this are "the same" (printed %f)


class LineError(Exception):
    """A line that cannot be used; ``kind`` is what :class:`LogProblems` counts it as."""

    def __init__(self, kind: str, detail: str = '') -> None:
        super().__init__(kind)
        self.kind = kind
        self.detail = detail


def guess_fov(num_beams: int) -> float:
    """The field of view CARMEN assumes for an old-format laser line of ``num_beams`` readings.

    Same rule as CARMEN's ``carmen_laser_guess_fov`` (``src/logtools/readlog.c``): a SICK LMS
    gives 181/361/401 beams over its full fan, and 180/360/400 when the last beam was dropped.
    """
    fov = {181: 180.0, 180: 179.0, 361: 180.0, 360: 179.5, 401: 100.0}.get(num_beams)
    if fov is not None:
        return math.radians(fov)
    if num_beams == 400:
        return math.pi / 100.0 * 99.75   # CARMEN's own expression (sic), kept for the same result
    return math.pi


def guess_angle_increment(num_beams: int) -> float:
    """The angle between beams CARMEN assumes for ``num_beams`` readings
    (``carmen_laser_guess_angle_increment``, ``src/logtools/readlog.c``)."""
    if num_beams in (180, 181):
        return math.pi / 180.0
    if num_beams in (360, 361):
        return math.pi / 360.0
    if num_beams in (400, 401):
        return math.pi / 720.0
    return guess_fov(num_beams) / (num_beams - 1) if num_beams > 1 else 0.0


@dataclasses.dataclass
class Mounts:
    """The lasers' poses on the robot as PARAM lines give them (CARMEN's robot module).

    ``robot_frontlaser_offset`` is how far ahead of the robot's centre the front laser sits; the
    rear laser looks backwards and ``robot_rearlaser_offset`` is how far it sits behind the centre:
    CARMEN's robot module puts the laser at ``odom + offset * (cos, sin)(odom_theta [+ pi])``
    (``src/robot/robot_laser.c``, ``construct_laser_message``).  Newer carmen.ini files add
    ``*_side_offset`` and ``*_angular_offset``, applied in the laser's own frame.  Raw lasers get
    the mount of the laser whose id ``robot_frontlaser_id`` / ``robot_rearlaser_id`` name (1, 2).
    """

    values: dict[str, float] = dataclasses.field(default_factory=dict)
    front_id: int = 1
    rear_id: int = 2

    _NAMES = ('offset', 'side_offset', 'angular_offset')

    def update(self, name: str, value: str) -> bool:
        """Take a PARAM line's ``name value``; False when the name is a mount's but the value is
        not a finite number (the caller says so; the mount keeps its value)."""
        for which in ('front', 'rear'):
            prefix = f'robot_{which}laser_'
            if not name.startswith(prefix):
                continue
            key = name[len(prefix):]
            if key not in self._NAMES and key != 'id':
                return True
            try:
                number = float(value)
            except ValueError:
                return False
            if not math.isfinite(number):
                return False
            if key == 'id':
                setattr(self, f'{which}_id', int(number))
            else:
                self.values[f'{which}_{key}'] = number
        return True

    def front(self) -> Pose2D:
        return tuple(self.values.get(f'front_{k}', 0.0) for k in self._NAMES)  # type: ignore[return-value]

    def rear(self) -> Pose2D:
        offset = tuple(self.values.get(f'rear_{k}', 0.0) for k in self._NAMES)
        return _pose(compose((0.0, 0.0, math.pi), offset))

    def of_channel(self, channel: str) -> Pose2D:
        """The mount PARAM lines give for ``channel`` (front, rear, rawN), else the robot's centre."""
        if channel == 'front' or channel == f'raw{self.front_id}':
            return self.front()
        if channel == 'rear' or channel == f'raw{self.rear_id}':
            return self.rear()
        return (0.0, 0.0, 0.0)


def _pose(values: object) -> Pose2D:
    x, y, theta = (float(v) for v in values)  # type: ignore[attr-defined]
    return (x, y, theta)


def _number(fields: list[str], i: int) -> float:
    try:
        return float(fields[i])
    except ValueError:
        raise LineError(f'{fields[0]} line with a field that is not a number',
                        f'field {i + 1} is {fields[i][:40]!r}') from None


def _count(fields: list[str], i: int) -> int:
    """A count (num_readings, num_remissions) at field ``i``; out of range means a cut line."""
    if i >= len(fields):
        raise LineError(f'truncated {fields[0]} line', f'{len(fields)} fields')
    try:
        count = int(fields[i])
    except ValueError:
        raise LineError(f'{fields[0]} line with a field that is not a number',
                        f'field {i + 1} (a count) is {fields[i][:40]!r}') from None
    if count < 0:
        raise LineError(f'{fields[0]} line with a negative count', f'field {i + 1} is {count}')
    return count


def _numbers(fields: list[str], start: int, stop: int) -> NDArray[np.float64]:
    try:
        return np.array(fields[start:stop], dtype=np.float64)
    except ValueError as error:
        raise LineError(f'{fields[0]} line with a field that is not a number', str(error)) from None


def _expect(fields: list[str], length: int) -> None:
    if len(fields) < length:
        raise LineError(f'truncated {fields[0]} line', f'{len(fields)} fields, the layout needs {length}')
    if len(fields) > length:
        raise LineError(f'malformed {fields[0]} line',
                        f'{len(fields)} fields, the layout has {length} (a wrong count?)')


def _tail_stamp(fields: list[str]) -> float:
    """The IPC timestamp of the line's tail; the logger's timestamp must be a number too."""
    stamp = _number(fields, len(fields) - 3)
    _number(fields, len(fields) - 1)
    if not math.isfinite(stamp):
        raise LineError(f'{fields[0]} line with a non-finite timestamp', fields[-3])
    return stamp


def _finite_pose(fields: list[str], start: int) -> Pose2D:
    pose = (_number(fields, start), _number(fields, start + 1), _number(fields, start + 2))
    if not all(math.isfinite(v) for v in pose):
        raise LineError(f'{fields[0]} line with a non-finite pose', ' '.join(fields[start:start + 3]))
    return pose


def _ranges(raw: NDArray[np.float64], max_range: float, min_range: float = 0.0) -> NDArray[np.float64]:
    """The records' conventions: NaN, inf and ``>= max_range`` saw nothing (inf); ``<= min_range``
    is no reading (NaN)."""
    ranges = raw.copy()
    ranges[~(raw < max_range)] = math.inf      # NaN compares false, so NaN lands here too
    ranges[raw <= min_range] = math.nan
    return ranges


def _mount(channel: str, robot: Pose2D, laser: Pose2D, mounts: Mounts) -> Pose2D:
    """The laser's pose on the robot: what the line's two poses imply when they differ, else what
    the PARAM lines say."""
    offset = _pose(relative(robot, laser))
    if max(abs(offset[0]), abs(offset[1]), abs(offset[2])) > _SAME_POSE:
        return offset
    return mounts.of_channel(channel)


def parse_odom(fields: list[str], where: str, mounts: Mounts) -> OdometryRecord:
    """``ODOM x y theta tv rv accel timestamp hostname logger_timestamp``."""
    _expect(fields, 7 + _TAIL)
    x, y, theta = _finite_pose(fields, 1)
    tv, rv, accel = (_number(fields, i) for i in (4, 5, 6))
    return OdometryRecord(_tail_stamp(fields), x, y, theta, tv, rv, accel, origin=where)


def parse_truepos(fields: list[str], where: str, mounts: Mounts) -> TruePoseRecord:
    """``TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_ts``."""
    _expect(fields, 7 + _TAIL)
    return TruePoseRecord(_tail_stamp(fields), _finite_pose(fields, 1), _finite_pose(fields, 4),
                          origin=where)


def parse_param(fields: list[str], where: str, mounts: Mounts) -> ParamRecord:
    """``PARAM module_variable value timestamp hostname logger_timestamp``; the value is text and
    may hold spaces."""
    if len(fields) < 2 + _TAIL:
        raise LineError('truncated PARAM line', f'{len(fields)} fields, the layout needs at least 5')
    return ParamRecord(_tail_stamp(fields), fields[1], ' '.join(fields[2:-_TAIL]), origin=where)


_OLD_CHANNELS = {'FLASER': 'front', 'RLASER': 'rear', 'LASER3': 'raw3', 'LASER4': 'raw4',
                 'REMISSIONFLASER': 'raw1', 'REMISSIONRLASER': 'raw2',
                 'REMISSIONLASER3': 'raw3', 'REMISSIONLASER4': 'raw4'}


def _old_config(n: int, mount: Pose2D) -> LaserConfig:
    return LaserConfig(OLD_START_ANGLE, guess_angle_increment(n), OLD_MAX_RANGE, 0.0, mount)


def parse_old_laser(fields: list[str], where: str, mounts: Mounts) -> ScanRecord:
    """``FLASER``/``RLASER num_readings r_1 .. r_n x y theta odom_x odom_y odom_theta`` + tail
    (the laser's pose, then the robot's odometry pose at the scan)."""
    n = _count(fields, 1)
    _expect(fields, 2 + n + 6 + _TAIL)
    channel = _OLD_CHANNELS[fields[0]]
    laser = _finite_pose(fields, 2 + n)
    robot = _finite_pose(fields, 5 + n)
    stamp = _tail_stamp(fields)
    config = _old_config(n, _mount(channel, robot, laser, mounts))
    ranges = _ranges(_numbers(fields, 2, 2 + n), config.max_range)
    return ScanRecord(stamp, ranges, config, channel, robot, laser, origin=where)


def parse_old_raw_laser(fields: list[str], where: str, mounts: Mounts) -> ScanRecord:
    """``LASER3``/``LASER4 num_readings r_1 .. r_n`` + tail, and the ``REMISSION*`` lines
    ``num_readings r_1 m_1 .. r_n m_n`` + tail (playback.c): the laser module's own scans."""
    n = _count(fields, 1)
    paired = fields[0].startswith('REMISSION')
    _expect(fields, 2 + (2 * n if paired else n) + _TAIL)
    channel = _OLD_CHANNELS[fields[0]]
    stamp = _tail_stamp(fields)
    values = _numbers(fields, 2, 2 + (2 * n if paired else n))
    config = _old_config(n, mounts.of_channel(channel))
    ranges = _ranges(values[0::2] if paired else values, config.max_range)
    return ScanRecord(stamp, ranges, config, channel, remissions=values[1::2] if paired else None,
                      origin=where)


def _fan(fields: list[str], trailing: int) -> tuple[int, int, int]:
    """Where the readings start, how many, and where the remissions start, for the new-format
    lines ``type start_angle fov resolution max_range accuracy [remission_mode] n r.. m m..``.
    CARMEN's logger has written remission_mode since 2006; older logs lack it: the layout whose
    counts fill the line exactly is the one used."""
    first_error: LineError | None = None
    for count_at in (8, 7):
        try:
            n = _count(fields, count_at)
            m = _count(fields, count_at + 1 + n)
            _expect(fields, count_at + 2 + n + m + trailing)
            return count_at + 1, n, count_at + 2 + n
        except LineError as error:
            first_error = first_error or error
    assert first_error is not None
    raise first_error


def _fan_config(fields: list[str], n: int, mount: Pose2D) -> tuple[LaserConfig, bool]:
    """The LaserConfig from the new-format fields, and whether the beams must be reversed (a
    negative resolution: clockwise beams, turned into the records' counter-clockwise order)."""
    start, fov, resolution, max_range = (_number(fields, i) for i in (2, 3, 4, 5))
    if not all(math.isfinite(v) for v in (start, resolution, max_range)) or max_range <= 0.0:
        raise LineError(f'{fields[0]} line with an impossible laser configuration',
                        f'start {start}, resolution {resolution}, max range {max_range}')
    if resolution < 0.0:
        return LaserConfig(start + (n - 1) * resolution, -resolution, max_range, 0.0, mount), True
    return LaserConfig(start, resolution, max_range, 0.0, mount), False


def _fan_values(fields: list[str], at: int, n: int, rem_at: int, m: int, config: LaserConfig,
                reverse: bool) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    ranges = _ranges(_numbers(fields, at, at + n), config.max_range)
    remissions = _numbers(fields, rem_at, rem_at + m) if m == n and m > 0 else None
    if reverse:
        ranges = ranges[::-1].copy()
        remissions = None if remissions is None else remissions[::-1].copy()
    return ranges, remissions


def parse_robot_laser(fields: list[str], where: str, mounts: Mounts) -> ScanRecord:
    """``ROBOTLASER1``/``2``: the fan, ranges, remissions, then ``laser_x laser_y laser_theta
    robot_x robot_y robot_theta tv rv forward_safety side_safety turn_axis`` + tail."""
    channel = {'ROBOTLASER1': 'front', 'ROBOTLASER2': 'rear'}[fields[0]]
    at, n, rem_at = _fan(fields, 11 + _TAIL)
    m = int(fields[rem_at - 1])
    pose_at = rem_at + m
    laser, robot = _finite_pose(fields, pose_at), _finite_pose(fields, pose_at + 3)
    for i in range(pose_at + 6, pose_at + 11):
        _number(fields, i)
    stamp = _tail_stamp(fields)
    config, reverse = _fan_config(fields, n, _mount(channel, robot, laser, mounts))
    ranges, remissions = _fan_values(fields, at, n, rem_at, m, config, reverse)
    return ScanRecord(stamp, ranges, config, channel, robot, laser, remissions, origin=where)


def parse_raw_laser(fields: list[str], where: str, mounts: Mounts) -> ScanRecord:
    """``RAWLASER1``..``4``: the fan, ranges and remissions + tail; no pose."""
    channel = f'raw{fields[0][-1]}'
    at, n, rem_at = _fan(fields, _TAIL)
    m = int(fields[rem_at - 1])
    stamp = _tail_stamp(fields)
    config, reverse = _fan_config(fields, n, mounts.of_channel(channel))
    ranges, remissions = _fan_values(fields, at, n, rem_at, m, config, reverse)
    return ScanRecord(stamp, ranges, config, channel, remissions=remissions, origin=where)


_Parser = Callable[[list[str], str, Mounts], OdometryRecord | TruePoseRecord | ParamRecord | ScanRecord]

PARSERS: dict[str, _Parser] = {
    'ODOM': parse_odom, 'TRUEPOS': parse_truepos, 'PARAM': parse_param,
    'FLASER': parse_old_laser, 'RLASER': parse_old_laser,
    'ROBOTLASER1': parse_robot_laser, 'ROBOTLASER2': parse_robot_laser,
    **{f'RAWLASER{i}': parse_raw_laser for i in range(1, 5)},
    **{name: parse_old_raw_laser for name in _OLD_CHANNELS if name not in ('FLASER', 'RLASER')}}


def parse_line(fields: list[str], where: str, mounts: Mounts
               ) -> OdometryRecord | TruePoseRecord | ParamRecord | ScanRecord | None:
    """The record of one line's fields, or None for a message type this reader does not know.

    :raises LineError: the line is cut, holds a field that is not a number, a non-finite pose or
        timestamp, or counts that do not fit the line.
    """
    parser = PARSERS.get(fields[0])
    return None if parser is None else parser(fields, where, mounts)
