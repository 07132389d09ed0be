"""The avoidModule's control (Pluto 6.2), free of any I/O: from the last accepted command, the laser,
the sonar and the pose, the command to write to the driveModule and the status to send up.

Per command type (:class:`pluto_motion.avoid_command.Kind`):

- velocity, regulator: passed to the drive (cmdFlags 0/10, 1/11: the sonar digit becomes the drive's
  +10) when the command arrives; with laser protection the linear speed is slowed by
  :class:`~pluto_motion.laser_guard.LaserGuard` and rewritten when the slowed value changes, but only
  within :data:`HAND_TIMEOUT_S` of the sender's last command, so that a silent sender still meets the
  drive's timeout (Pluto 6.1: "when driving by hand it can cause the robot to stop").
- goto: :func:`~pluto_motion.goto_field.goto_step` every loop, written as a regulator command (heading
  and speed) every loop, so the drive's 4 s timeout never fires during a goto (Pluto 6.1: "If one is
  using the avoidModule goto this timeout will not occur").  Reached or stuck: the robot is held
  stopped (a zero velocity command every loop) until the next command.
- wall follow: :func:`~pluto_motion.wall_follow.wall_follow_step` every loop, as velocity commands.
  It needs the laser, so a dead laser stops it (code 7) whatever the avoidance digit.

With laser protection on, a dead laser (:class:`~pluto_motion.laser_guard.LaserWatch`) stops the
robot: element[0] = 7 (fail closed).  A slowing by the laser is element[0] = 6.  In both cases
data[0..1] are the velocities the avoidModule commands (slowed); otherwise data and element[0] are
the drive's.  Release (-1) writes one stop to the drive and then nothing, so another program may
drive it.  Readings are moved into the current robot frame by the pose change since they were
taken.  With laser protection on, the speed is then timed against walkers (:mod:`.passage`):
the robot goes on, waits, backs off or steps forward; element[0] = 6 while it does.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .avoid_command import AvoidCommand, Kind
from .goto_field import FieldSettings, GotoProgress, goto_step
from .laser_guard import LASER_FATAL, LASER_SLOW, GuardLimits, LaserGuard, LaserWatch, free_distance
from .moving_obstacles import MovingObstacles, View
from .passage import PassageSettings, Walker, passage_speed
from .wall_follow import wall_follow_step

__all__ = ['GOTO_NORMAL', 'GOTO_REACHED', 'GOTO_STUCK', 'HAND_TIMEOUT_S', 'THREAD_STOPPED', 'AvoidController',
           'DriveOrder']

#: element[1] codes of ``avoidance/status`` (Pluto 6.2).
GOTO_REACHED, GOTO_STUCK, GOTO_NORMAL, THREAD_STOPPED = 1, 2, -1, -10
#: The drive's timeout (Pluto 6.1, "about 4 sec"): laser slowing rewrites a hand command no longer.
HAND_TIMEOUT_S = 4.0


@dataclasses.dataclass(frozen=True)
class DriveOrder:
    """One ``drive/command`` request."""

    cmd_flags: int
    velocity: tuple[float, ...]
    position: tuple[float, ...] = ()


def _stop(sonar: bool = False) -> DriveOrder:
    return DriveOrder(10 if sonar else 0, (0.0, 0.0))


def _relative(points: np.ndarray, then: tuple[float, float, float] | None,
              now: tuple[float, float, float] | None) -> np.ndarray:
    """``points`` taken in the robot frame at pose ``then``, in the robot frame at pose ``now``."""
    if then is None or now is None or len(points) == 0 or then == now:
        return points
    c, s = math.cos(then[2]), math.sin(then[2])
    wx, wy = then[0] + c * points[:, 0] - s * points[:, 1], then[1] + s * points[:, 0] + c * points[:, 1]
    dx, dy = wx - now[0], wy - now[1]
    c, s = math.cos(now[2]), math.sin(now[2])
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy))


class AvoidController:
    """The avoid thread's state; feed :meth:`accept`, :meth:`set_laser`, :meth:`set_sonar` and call
    :meth:`step` once per loop."""

    def __init__(self, field: FieldSettings = FieldSettings(), guard: GuardLimits = GuardLimits(),
                 stale_s: float | None = None) -> None:
        self.field = field
        self.guard = LaserGuard(guard)
        self.watch = LaserWatch(stale_s)
        self.progress = GotoProgress(field)
        self.running = True
        self.command: AvoidCommand | None = None
        self.command_at = -math.inf
        self.fresh = False
        self.side = 0
        self.goto_code = 0
        self.laser_code = 0
        self.slowed: tuple[float, float] | None = None
        self.written: DriveOrder | None = None
        self.stop_sent = True
        self.failure: str | None = None
        #: Why the last goto got stuck (for the log).
        self.stuck_reason = ''
        self.laser: tuple[np.ndarray, tuple[float, float, float] | None] = (np.zeros((0, 2)), None)
        self.sonar: tuple[np.ndarray, np.ndarray, tuple[float, float, float] | None] = (
            np.zeros((0, 2)), np.zeros(0), None)
        #: People and other things the laser sees walk, and the passage timed against them.
        self.movers = MovingObstacles()
        self.passage = PassageSettings(radius=guard.radius)
        self.walkers: list[Walker] = []
        #: The robot's linear speed now (m/s): the drive's output, for timing the passage.
        self.speed = 0.0

    def tune(self, field: FieldSettings, guard: GuardLimits) -> None:
        """Use these settings from now on (tunables a user changed while the module runs)."""
        self.field = self.progress.settings = field
        self.guard.limits = guard
        self.passage = dataclasses.replace(self.passage, radius=guard.radius)

    # -- inputs ----------------------------------------------------------------------------------
    def accept(self, command: AvoidCommand, now: float) -> None:
        """A new command replaces the old (a new goto starts afresh)."""
        self.command, self.command_at, self.fresh = command, now, True
        self.side = 0
        self.goto_code = GOTO_NORMAL if command.kind is Kind.GOTO else 0
        self.progress.start(now)

    def set_running(self, running: bool) -> None:
        """Start or stop the avoid thread; stopping forgets the command and writes one stop."""
        if running == self.running:
            return
        self.running = running
        self.command, self.goto_code, self.laser_code, self.slowed = None, 0, 0, None
        self.stop_sent = running

    def set_laser(self, ranges: list[float], points: np.ndarray, stamp: float, now: float,
                  pose: tuple[float, float, float] | None, view: View | None = None) -> None:
        """A scan: its raw ranges (for the fatal check), its echoes in the robot frame, its stamp;
        ``view`` where the laser is and the bearings of its first and last beams."""
        self.watch.scan(ranges, stamp, now)
        self.laser = (points, pose)
        self.movers.scan(points, pose, stamp, view)

    def set_sonar(self, points: np.ndarray, cones: np.ndarray, pose: tuple[float, float, float] | None) -> None:
        self.sonar = (points, cones, pose)

    def forget_poses(self) -> None:
        """The poses the kept readings were taken at are of another frame: use the readings as they
        are (in the robot frame when taken) until new ones come."""
        self.laser = (self.laser[0], None)
        self.sonar = (self.sonar[0], self.sonar[1], None)
        self.movers.forget()

    # -- one loop --------------------------------------------------------------------------------
    def step(self, now: float, pose: tuple[float, float, float] | None,
             frame: tuple[float, float, float] | None = None) -> DriveOrder | None:
        """The drive command to write now (None: write nothing).  ``pose`` is the robot's, the
        goto's frame; ``frame`` the robot's pose in the frame the readings were placed in (None:
        ``pose``'s): a continuous one, so that a correction of ``pose`` is not taken for motion."""
        frame = pose if frame is None else frame
        self.laser_code, self.slowed = 0, None
        if not self.running:
            if self.stop_sent:
                return None
            self.stop_sent = True
            return _stop()
        c = self.command
        if c is None:
            return None
        fresh, self.fresh = self.fresh, False
        self.failure = self.watch.failure(now)
        laser_points = _relative(self.laser[0], self.laser[1], frame) if self.failure is None else np.zeros((0, 2))
        self.walkers = self.movers.walkers(frame) if self.failure is None else []
        sonar_points = _relative(self.sonar[0], self.sonar[2], frame)
        if c.laser and self.failure is not None or c.kind is Kind.WALL_FOLLOW and self.failure is not None:
            self.laser_code, self.slowed = LASER_FATAL, (0.0, 0.0)
            return _stop(c.sonar)
        if c.kind is Kind.VELOCITY or c.kind is Kind.REGULATOR:
            return self._pass(c, now, fresh, laser_points, sonar_points)
        if c.kind is Kind.WALL_FOLLOW:
            tv, rv = wall_follow_step(laser_points, c.tv, c.distance, radius=self.field.radius)
            tv = self._timed(c, self._guarded(c, tv, rv, laser_points), rv, laser_points, sonar_points)
            return DriveOrder(10 if c.sonar else 0, (tv, rv))
        return self._goto(c, now, pose, laser_points, sonar_points)

    def _guarded(self, c: AvoidCommand, tv: float, rv: float, points: np.ndarray,
                 wanted: float | None = None) -> float:
        if not c.laser:
            return tv
        limited, code = self.guard.limit(tv, points, wanted)
        if code:
            self.laser_code, self.slowed = code, (limited, rv)
        return limited

    def _timed(self, c: AvoidCommand, tv: float, rv: float, laser_points: np.ndarray,
               sonar_points: np.ndarray) -> float:
        """``tv`` timed against the walkers (:mod:`~pluto_motion.passage`): go on, wait, back off or
        step forward out of the way (as fast as backing off, and as what is ahead allows).  Backing
        off only with a sonar reading that is fresh (the laser looks forward) and clear behind."""
        if not c.laser or not self.walkers or tv < 0.0:
            return tv
        settings = self.passage
        if settings.back > 0.0 and (self.sonar[2] is None or free_distance(
                sonar_points, settings.radius, self.guard.limits.margin, math.pi) < self.guard.limits.slow):
            settings = dataclasses.replace(settings, back=0.0)
        ahead = self.guard.limit(self.passage.back, laser_points)[0]
        plan = passage_speed(self.walkers, self.speed, tv, settings, ahead)
        if plan is None:
            return tv
        self.laser_code, self.slowed = LASER_SLOW, (plan[0], rv)
        return plan[0]

    def _pass(self, c: AvoidCommand, now: float, fresh: bool, points: np.ndarray,
              sonar_points: np.ndarray) -> DriveOrder | None:
        rv = c.rv if c.kind is Kind.VELOCITY else math.nan
        tv = self._timed(c, self._guarded(c, c.tv, rv, points), rv, points, sonar_points)
        if c.kind is Kind.VELOCITY:
            order = DriveOrder(10 if c.sonar else 0, (tv, c.rv))
        else:
            order = DriveOrder(11 if c.sonar else 1, (tv,), (0.0, c.heading))
        if fresh or (order != self.written and now - self.command_at < HAND_TIMEOUT_S):
            self.written = order
            return order
        return None

    def _goto(self, c: AvoidCommand, now: float, pose: tuple[float, float, float] | None,
              laser_points: np.ndarray, sonar_points: np.ndarray) -> DriveOrder:
        if self.goto_code in (GOTO_REACHED, GOTO_STUCK) or pose is None:
            return _stop(c.sonar)
        points = np.concatenate((laser_points, sonar_points))
        cones = np.concatenate((np.zeros(len(laser_points)), self.sonar[1][:len(sonar_points)]))
        step = goto_step(pose, c.goal, points, max_tv=c.max_tv, max_rv=c.max_rv, strength=c.strength,
                         side=self.side, cones=cones, settings=self.field)
        self.side = step.side
        if step.reached:
            self.goto_code = GOTO_REACHED
            return _stop(c.sonar)
        why = self.progress.stuck(step, now)
        if why is not None:
            self.goto_code, self.stuck_reason = GOTO_STUCK, f'goto stuck at {pose[0]:.2f}, {pose[1]:.2f}: {why}'
            return _stop(c.sonar)
        self.goto_code = GOTO_NORMAL
        speed = self._guarded(c, step.speed, math.nan, laser_points, wanted=c.max_tv)
        speed = self._timed(c, speed, math.nan, laser_points, sonar_points)
        return DriveOrder(11 if c.sonar else 1, (speed,), (0.0, step.heading))

    # -- status ----------------------------------------------------------------------------------
    def status(self, drive_data: list[float], drive_element: list[int],
               refused: int) -> tuple[list[float], list[int]]:
        """``avoidance/status``: data[0..1], element[0] (drive's or laser 6/7), element[1] (goto /
        thread), element[2] (ours: refused commands)."""
        if self.laser_code and self.slowed is not None:
            # The regulator's and the goto's angular velocity is the drive's (nan here).
            rv = self.slowed[1] if math.isfinite(self.slowed[1]) else (drive_data[1] if len(drive_data) > 1 else 0.0)
            data, code = [self.slowed[0], float(rv)], self.laser_code
        else:
            data = [float(v) for v in drive_data[:2]] or [0.0, 0.0]
            code = int(drive_element[0]) if drive_element else 0
        second = THREAD_STOPPED if not self.running else self.goto_code
        return data, [code, second, refused]
