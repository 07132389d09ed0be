"""``carmen_log play``: a CARMEN log played onto the streams the robot's base and laser supply.

    carmen_log play LOG [-R RATE] [-b BASE] [-s LASER] [-L CHANNEL] [-w SECONDS] [-W MODULES] [-k] [-t] [-n NAME]

A WURDE module that supplies, from the log, what the simulated robot's dummies supply
(``<BASE>Motion``, ``<LASER>`` with its info, ``<LASER>/Timing`` and the ROS mirrors of
:mod:`.carmen_log_ros`), so that the localModule, poseModule and slamModule run on it as on the
robot.  docs/real-data.md ("Real robots' data") gives the usage; docs/pluto-nav.md ("carmen_log play")
each stream's content, the pace and the waits.

Before changing it: what is published before a reader exists reaches nobody, so before the first
message it waits (``-w``, ``-W``) for its readers, and at ``-R 0`` each message waits (at most
:data:`ACK_DEADLINE_S`) until every matched reader acknowledged it.  ``-R`` and ``-L`` are not
``-r`` and ``-l`` because those are every WURDE module's registration and capability options,
which the MCP uses.  At the end it exits 0 (``-k``: it stays until told to quit), so under the MCP
it is ``managed="unmanaged"``: a managed module that exits is started again and would replay the log.
"""

from __future__ import annotations

import getopt
import math
import os
import pathlib
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any

from rclpy.duration import Duration
from wurde_core import CommsManager, Pose, RunState, Time
from wurde_core.interfaces import Egomotion, FVectorState, RangeFinder
from wurde_core.module_loop import MODULE_TTL_S, run_loop, set_loop
from wurde_core.naming import relative_topic
from wurde_core.options import STANDARD_SPEC, split_ros_arguments

from .carmen_log_ros import PlayMirrors
from .logs import LaserConfig, LogError, LogProblems, OdometryRecord, RobotLog, ScanRecord
from .logs.formats import open_records
from .logs.robot_log import assemble

__all__ = ['Player', 'main']

USER_SPEC = 'R:b:s:L:w:W:kt'
HELP = ('  LOG         the CARMEN log (plain or gzip)\n'
        '  -R RATE     pace: 1 the log\'s (default), 4 four times faster, 0 as fast as the readers take it\n'
        '  -b BASE     base stream prefix: odometry on <BASE>Motion (default PlutoBase)\n'
        '  -s LASER    laser stream: <LASER> and <LASER>/Timing (default PlutoLaser)\n'
        '  -L CHANNEL  the log\'s laser: front, rear, raw1..raw4 (default: the front one)\n'
        '  -w SECONDS  longest wait for the laser stream\'s readers before the first message (default 10)\n'
        '  -W MODULES  comma-separated modules that must read the streams before the first message\n'
        '  -k          keep running after the end of the log (until told to quit)\n'
        '  -t          also publish odom -> base_link on /tf (when no localModule runs)')
LOOP_S = 0.01
#: Longest wait for one message's acknowledgements at ``-R 0`` before going on (counted).
ACK_DEADLINE_S = 10.0
#: Longest wait, at the end, for the last messages to be acknowledged before the process ends.
FINAL_ACK_S = 5.0
_ACK_SLICE_S = 0.05
_STEP_BUDGET_S = 0.05
_SAME = 1e-4


def _config_key(config: LaserConfig) -> tuple[int, ...]:
    values = (config.start_angle, config.angular_resolution, config.max_range, *config.mount)
    return tuple(round(v / _SAME) for v in values)


class Player:
    """The module's state: the log's events in time order and where the playing is."""

    def __init__(self, manager: CommsManager, log: RobotLog | None, *, base: str, laser: str,
                 rate: float, wait_s: float, keep_alive: bool, tf: bool,
                 say: Callable[[str], None], readers: Sequence[str] = ()) -> None:
        self.manager, self.log, self.rate, self.keep_alive, self.say = manager, log, rate, keep_alive, say
        self.laser_name = laser
        self.readers = [name for name in readers if name]
        self.motion = Egomotion(f'{base}Motion')
        self.scan = RangeFinder(laser)
        self.timing = FVectorState(f'{laser}/Timing')
        # Paced, a burst must not replace an event not yet sent: queue mode (a deep writer).  At
        # -R 0 every message waits for its acknowledgements, so one is never outstanding, and a
        # writer of depth 1 is acknowledged at once (Fast DDS piggybacks a heartbeat on each
        # sample only when its history is that shallow; a deep one waits for the periodic
        # heartbeat, up to 3 s).
        deep = rate > 0
        for obj in self.objects:
            obj.set_auto_timestamp(False)
            obj.set_queue_mode(deep)
            manager.register_supplier(obj)
        self.mirrors = (PlayMirrors(manager.node, base=base, laser=laser, tf=tf, depth=10 if deep else 1)
                        if log is not None else None)
        events: list[tuple[float, int, OdometryRecord | ScanRecord]] = []
        if log is not None:
            events += [(r.stamp, 0, r) for r in log.odometry]      # odometry first at equal stamps
            events += [(s.stamp, 1, s) for s in log.scans]
        events.sort(key=lambda e: (e[0], e[1]))
        self.events = events
        self.next = 0
        self.wait_deadline = time.monotonic() + wait_s
        self.started = False
        self.finished = False
        self.delivered = False
        self.wall_start = 0.0
        self.paused_at: float | None = None
        self.pending: tuple[list[Callable[[float], bool]], float] | None = None
        self.announced: tuple[int, ...] | None = None
        self.counts = {'scans': 0, 'odometry': 0, 'unacknowledged': 0}
        manager.on_state(RunState.IDLE, self._pause)
        manager.on_state(RunState.RUN, self._resume)

    @property
    def objects(self) -> list[Any]:
        return [self.motion, self.scan, self.timing]

    # -- before the first message ---------------------------------------------------------------
    def _readers_ready(self) -> bool:
        """The laser stream has a reader, and every reader the graph shows of the streams and
        their mirrors is matched (with two readers, the first matched is not enough)."""
        if self.scan.peers('data') < 1:
            return False
        node = self.manager.node
        if not all(obj.peers('data') >= node.count_subscribers(relative_topic(obj.stream, 'data'))
                   for obj in self.objects):
            return False
        mirrors = self.mirrors.publishers if self.mirrors is not None else []
        if not all(p.get_subscription_count() >= node.count_subscribers(p.topic_name) for p in mirrors):
            return False
        topics = {relative_topic(obj.stream, 'data') for obj in self.objects}
        return all(topics & self._read_by(name) for name in self.readers)

    def _read_by(self, name: str) -> set[str]:
        """The topics the node ``name`` (a module's) subscribes to, without the leading slash."""
        namespace, _, base = name.rpartition('/')
        try:
            found = self.manager.node.get_subscriber_names_and_types_by_node(base, namespace or '/')
        except Exception:              # NodeNameNonExistentError: not in the graph yet
            return set()
        return {topic.lstrip('/') for topic, _ in found}

    def _begin(self, now: float) -> None:
        assert self.log is not None
        if not self._readers_ready():
            self.say(f'no reader of {self.laser_name} matched within the wait: playing anyway')
        self.motion.info.origin.set_value(Pose(0.0, 0.0, 0.0))
        self.motion.publish_info()
        self.started, self.wall_start = True, now
        pace = 'as fast as the readers take it' if self.rate == 0 else f'at {self.rate:g} x its pace'
        self.say(f'playing {self.log.path}: {len(self.log.scans)} scans and {len(self.log.odometry)} '
                 f'odometry records over {self.log.duration:.1f} s, {pace}')

    # -- pausing while Idle ----------------------------------------------------------------------
    def _pause(self) -> None:
        self.paused_at = time.monotonic()

    def _resume(self) -> None:
        if self.paused_at is not None and self.started:
            self.wall_start += time.monotonic() - self.paused_at
        self.paused_at = None

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        for obj in self.objects:
            while obj.get_next_request():
                pass                       # nobody re-bases or re-configures a log
        if self.log is None or self.finished:
            return
        now = time.monotonic()
        if not self.started:
            if not self._readers_ready() and now < self.wait_deadline:
                return
            self._begin(now)
        if self.next < len(self.events):
            if self.rate > 0:
                self._paced()
            else:
                self.manager.set_no_sleep()
                self._unpaced()
            return
        if self.pending is not None and not self._acknowledged(count=self.rate == 0):
            return                         # the last messages' acknowledgements (loop on: beats)
        if not self.delivered:
            self.delivered = True          # the last messages: the readers must have them before
            waits = [self._wurde_wait(obj) for obj in self.objects]      # the process ends
            waits += [self._ros_wait(p) for p in (self.mirrors.publishers if self.mirrors else [])]
            self.pending = (waits, time.monotonic() + FINAL_ACK_S)
            self.manager.set_sleep_only(LOOP_S)
            return
        self._finish()

    def _paced(self) -> None:
        due = 0.0
        while self.next < len(self.events):
            due = self.wall_start + (self.events[self.next][0] - self.events[0][0]) / self.rate
            if due > time.monotonic():
                break
            self._publish_next()
        wait = due - time.monotonic() if self.next < len(self.events) else LOOP_S
        self.manager.set_sleep_only(min(LOOP_S, max(0.0, wait)))

    def _unpaced(self) -> None:
        end = time.monotonic() + _STEP_BUDGET_S
        while time.monotonic() < end:
            if self.pending is not None and not self._acknowledged():
                return
            if self.next >= len(self.events):
                return
            waits = self._publish_next()
            self.pending = (waits, time.monotonic() + ACK_DEADLINE_S)

    def _acknowledged(self, *, count: bool = True) -> bool:
        """Whether the last message's readers all acknowledged it (or its deadline passed, then
        ``count`` it); each wait is a short slice, so the loop goes on beating meanwhile."""
        assert self.pending is not None
        waits, deadline = self.pending
        left = [wait for wait in waits if not wait(_ACK_SLICE_S)]
        if left and time.monotonic() < deadline:
            self.pending = (left, deadline)
            return False
        if left and count:
            self.counts['unacknowledged'] += 1
        self.pending = None
        return True

    def _publish_next(self) -> list[Callable[[float], bool]]:
        """Publish the next event; the waits for its acknowledgements."""
        assert self.mirrors is not None
        _, _, record = self.events[self.next]
        self.next += 1
        if isinstance(record, OdometryRecord):
            data = self.motion.data
            data.location = Pose(record.x, record.y, record.theta)
            data.tv, data.rv, data.acceleration = record.tv, record.rv, record.acceleration
            data.timestamp = Time(record.stamp)
            self.motion.publish_data()
            self.counts['odometry'] += 1
            return [self._wurde_wait(self.motion), *map(self._ros_wait, self.mirrors.publish_odometry(record))]
        waits = []
        if _config_key(record.config) != self.announced:
            self._announce(record.config)
            waits += [self._wurde_wait(self.scan, 'info'), self._ros_wait(self.mirrors.static)]
        ranges = [float(r) for r in record.ranges]
        self.scan.data.ranges = ranges
        self.scan.data.timestamp = Time(record.stamp)
        self.scan.publish_data()
        self.timing.data.element = [len(ranges)]
        self.timing.data.data = []
        self.timing.data.timestamp = Time(record.stamp)
        self.timing.publish_data()
        config = record.config
        ros = self.mirrors.publish_scan(ranges, record.stamp, first=config.mount[2] + config.start_angle,
                                        step=config.angular_resolution, max_range=config.max_range)
        self.counts['scans'] += 1
        return [*waits, self._wurde_wait(self.scan), self._wurde_wait(self.timing), *map(self._ros_wait, ros)]

    def _announce(self, config: LaserConfig) -> None:
        """The RangeFinder info of the laser's fan and mount (and its ``/tf_static`` mirror)."""
        assert self.mirrors is not None
        x, y, yaw = config.mount
        info = self.scan.info
        info.max_range.set_value(config.max_range)
        info.uniform.set_value(True)
        info.half_angle.set_value(config.angular_resolution / 2)
        info.x_offset.set_value(x)
        info.y_offset.set_value(y)
        info.z_offset.set_value(0.0)
        info.theta_offset.set_value(yaw + config.start_angle)
        info.theta_separation.set_value(config.angular_resolution)
        self.scan.publish_info()
        self.mirrors.announce(x, y, 0.0)
        self.announced = _config_key(config)

    @staticmethod
    def _wurde_wait(obj: Any, channel: str = 'data') -> Callable[[float], bool]:
        return lambda timeout: bool(obj.wait_delivered(timeout, channel))

    @staticmethod
    def _ros_wait(publisher: Any) -> Callable[[float], bool]:
        return lambda timeout: bool(publisher.wait_for_all_acked(Duration(seconds=timeout)))

    # -- the end ---------------------------------------------------------------------------------
    def summary(self) -> str:
        assert self.log is not None
        c = self.counts
        late = f', {c["unacknowledged"]} not acknowledged in time' if c['unacknowledged'] else ''
        done = 'played' if self.finished else f'stopped after {self.next} of {len(self.events)} messages:'
        return (f'{done} {c["scans"]} scans ({self.log.scans[0].channel if self.log.scans else "-"} laser) '
                f'and {c["odometry"]} odometry records of {self.log.path}{late} '
                f'(log problems: {self.log.problems.summary()})')

    def _finish(self) -> None:
        self.finished = True
        self.say(self.summary())
        self.manager.set_sleep_only(LOOP_S)
        if not self.keep_alive:
            self.manager.set_state(RunState.QUIT)

    def close(self) -> None:
        if self.log is not None and self.started and not self.finished:
            self.say(self.summary())


def _options_first(argv: list[str]) -> list[str]:
    """``argv`` with the options before ``LOG`` (WURDE's parser stops at the first argument, and
    the MCP appends ``-r`` after the configured ones)."""
    own, ros = split_ros_arguments(argv[1:])
    try:
        pairs, rest = getopt.gnu_getopt(own, STANDARD_SPEC + USER_SPEC)
    except getopt.GetoptError:
        return argv                        # the WURDE parser says what is wrong
    flat = [item for flag, value in pairs for item in ((flag, value) if value else (flag,))]
    return [argv[0], *flat, *(['--'] if rest else []), *rest, *ros]


def _number(user: dict[str, str], letter: str, default: float) -> float:
    text = user.get(letter)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise ValueError(f'-{letter} {text}: a number >= 0')
    return value


def _load(path: pathlib.Path, channel: str | None, program: str) -> RobotLog:
    """The log with the scans of ``channel`` (default: the front laser, else as
    :func:`~pluto_nav.logs.robot_log.assemble` chooses); the log's problems are warned on stderr.

    :raises LogError: the log cannot be read, or has no scans (of ``channel``).
    """
    problems = LogProblems(lambda text: print(f'{program}: {text}', file=sys.stderr, flush=True))
    records = list(open_records(path, problems))
    channels = sorted({r.channel for r in records if isinstance(r, ScanRecord)})
    if channel is not None and channel not in channels:
        raise LogError(f'{path}: no scans of the laser {channel} (it has {", ".join(channels) or "no laser"})')
    if not channels:
        raise LogError(f'{path}: no laser scans to play')
    return assemble(str(path), records, problems, laser=channel)


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    program = argv[0] if argv else 'carmen_log play'
    manager = CommsManager('carmenLog')
    manager.set_help_string(HELP)
    opts = manager.parse_options(_options_first(argv), USER_SPEC)
    user = opts.user

    def say(text: str) -> None:
        print(f'{manager.name}: {text}', flush=True)

    try:
        rate, wait_s = _number(user, 'R', 1.0), _number(user, 'w', 10.0)
    except ValueError as error:
        print(f'{program}: {error}', file=sys.stderr, flush=True)
        return 2
    log = None
    if not (opts.registration or opts.list_capabilities):
        if len(opts.arguments) != 1:
            print(f'{program}: one LOG is needed (got {len(opts.arguments)} arguments); -h for help',
                  file=sys.stderr, flush=True)
            return 2
        try:
            log = _load(pathlib.Path(opts.arguments[0]), user.get('L'), os.path.basename(program))
        except LogError as error:
            print(f'{program}: {error}', file=sys.stderr, flush=True)
            return 2
    player = Player(manager, log, base=user.get('b', 'PlutoBase'), laser=user.get('s', 'PlutoLaser'), rate=rate,
                    wait_s=wait_s, keep_alive='k' in user, tf='t' in user, say=say,
                    readers=user.get('W', '').split(','))
    set_loop(manager, LOOP_S, MODULE_TTL_S)
    return run_loop(manager, player.step, player.close)


if __name__ == '__main__':
    sys.exit(main())
