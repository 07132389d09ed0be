"""synchro_mover: WURDE's SynchroMover (guide 7.3), a VectorMoverTransport supplier.

"SynchroMover is an implementation of the VectorMover/VectorMoverTransport interface ... it does
not queue commands; when it receives a new goal point, it overrides its current goal point ... it
requires ... sources of Egomotion ... and RobotDrive capabilities" (7.3).  Consumers use the
:class:`wurde_core.wrappers.VectorMover` class: ``move(PVector)``, ``move_to(x, y)``, ``stop()``.
It also supplies the NavigatorTransport view ``<name>Navigator`` that the guide's chapter-1
mapping gives VectorMover (a goal in the Egomotion frame).  docs/pluto-motion.md ("SynchroMover")
has its streams and options; ``-h`` lists the options too.

Before changing it: a vector is relative to the robot when it is sent and is fixed in the
odometry frame then, kept through a restart of the base (:mod:`pluto_nav.continuous_odometry`).
It fails safe: with the brake on, or no odometry for :data:`EGO_STALE_S`, the robot is stopped.
The consumers are STRAT_ASSIGNED (the MCP maps them, as in the guide's configurations) unless
options name their streams.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable

from pluto_nav.continuous_odometry import ContinuousOdometry
from wurde_core import CommsManager, Logger, Point, Pose
from wurde_core.interfaces import Egomotion, NavigatorTransport, RobotDrive, SynchroDrive, VectorMoverTransport
from wurde_core.module_loop import run_loop, set_loop

from .assigned import consumer
from .vector_follower import MoverLimits, VectorFollower

__all__ = ['SynchroMover', 'main']

LOOP_S = 0.05
#: Odometry older than this (s) is no odometry: the mover stops the robot.
EGO_STALE_S = 0.5
#: Seconds between publications of an unchanged state.
STATUS_PERIOD_S = 1.0
#: A pose (x, y, theta) in the odometry frame.
Pose2 = tuple[float, float, float]
#: NavigatorTransport stop reasons (see its interface description).
STOP_NONE, STOP_REACHED, STOP_USER, STOP_OTHER = 0, 1, 2, 3
HELP = ('  -d DRIVE     the base drive stream (default: assigned by the MCP to DriveClient)\n'
        '  -e EGO       the Egomotion stream (default: assigned by the MCP to EgoClient)\n'
        '  -k KIND      robot (RobotDrive, default) or synchro (SynchroDrive)\n'
        '  -v MAX_TV    translational speed limit, m/s (0.5)\n'
        '  -w MAX_RV    rotational speed limit, rad/s (1.0)')



class SynchroMover:
    """The streams around a :class:`VectorFollower`."""

    def __init__(self, manager: CommsManager, logger: Logger, limits: MoverLimits, *, synchro: bool,
                 drive: str | None = None, ego: str | None = None) -> None:
        self.manager, self.logger = manager, logger
        self.follower = VectorFollower(limits)
        self.synchro = synchro
        self.mover = VectorMoverTransport(manager.name)
        self.navigator = NavigatorTransport(f'{manager.name}Navigator')
        self.drive = consumer(SynchroDrive if synchro else RobotDrive, drive, 'DriveClient')
        self.ego = consumer(Egomotion, ego, 'EgoClient')
        for obj in (self.mover, self.navigator):
            obj.set_queue_mode(True)              # every goal counts, the last one wins
            manager.register_supplier(obj)
        for obj in (self.drive, self.ego):
            manager.register_consumer(obj)
        #: Odometry in one frame through restarts of the base (goals are fixed in it).
        self.odometry = ContinuousOdometry()
        self.resets_seen = 0
        self.pose: tuple[float, float, float] | None = None
        self.pose_at = -math.inf
        self.brake = True
        self.caps: tuple[float | None, float | None] = (None, None)
        self.stop_reason = STOP_NONE
        self.moving = False
        #: A goal that came before the first odometry, applied when it comes.
        self.waiting: tuple[Callable[[Pose2], None], str] | None = None
        self.sent: tuple | None = None
        self.sent_at = -math.inf
        self._publish_info()

    # -- inputs ----------------------------------------------------------------------------------
    def _take_requests(self) -> None:
        while self.mover.get_next_request():
            r = self.mover.requests
            self.brake = bool(r.brake.get_value())
            self.caps = (float(r.max_trans_speed.get_value()) or None, float(r.max_rot_speed.get_value()) or None)
            vector = r.vector.get_value()
            self._goal(lambda pose: self.follower.set_vector(pose, vector.magnitude(), vector.angle()),
                       f'vector ({vector.magnitude():.2f} m, {vector.angle():.2f} rad)')
            self._publish_info()
        while self.navigator.get_next_request():
            r = self.navigator.requests
            if not bool(r.autonomous.get_value()):
                self.follower.stop()
                self.stop_reason = STOP_USER
                continue
            if r.goal_place.get_value():
                self.logger.warn(f'{self.manager.name}: goal place {r.goal_place.get_value()!r} ignored: '
                                 'the mover has no map')
            goal = r.goal.get_value()
            self.brake = False
            self._goal(lambda pose: self.follower.set_goal(goal.x(), goal.y()),
                       f'goal ({goal.x():.2f}, {goal.y():.2f})')

    def _goal(self, apply: Callable[[Pose2], None], what: str) -> None:
        if self.brake:
            self.follower.stop()
            return
        if self.pose is None:
            self.waiting = (apply, what)           # fixed at the first pose (relative to it)
            return
        self.waiting = None
        try:
            apply(self.pose)
        except ValueError as error:
            self.logger.warn(f'{self.manager.name}: {what} refused: {error}')
            return
        self.stop_reason = STOP_NONE

    def _take_odometry(self, now: float) -> None:
        while self.ego.get_next_data():
            self.pose, self.pose_at = self.odometry.take(self.ego.data), now
        if self.odometry.resets != self.resets_seen:
            self.resets_seen = self.odometry.resets
            self.logger.warn(f'{self.manager.name}: the odometry started again from zero (its base '
                             f'restarted?): the goal is kept where it was; {self.odometry.describe_bridge()}')

    # -- outputs ---------------------------------------------------------------------------------
    def _command(self, tv: float, rv: float) -> None:
        r = self.drive.requests
        r.brake.set_value(False)
        if self.synchro:
            r.trans.set_value(tv)
            r.angular.set_value(rv)
        else:
            r.mode.set_value(0)
            r.trans_velocity.set_value(tv)
            r.rot_velocity.set_value(rv)
        self.drive.publish_request()

    def _publish_info(self) -> None:
        info = self.mover.info
        info.brake.set_value(self.brake)
        tv, rv = self.caps
        info.max_trans_speed.set_value(tv or self.follower.limits.max_tv)
        info.max_rot_speed.set_value(rv or self.follower.limits.max_rv)
        self.mover.publish_info()

    def _publish_state(self, now: float, tv: float, rv: float, distance: float, angle: float) -> None:
        done = not self.follower.active
        value = (round(tv, 4), round(rv, 4), round(distance, 3), round(angle, 3), done, self.stop_reason)
        if value == self.sent and now - self.sent_at < STATUS_PERIOD_S:
            return
        data = self.mover.data
        data.trans_velocity, data.rot_velocity = tv, rv
        data.distance_remaining, data.angle_remaining, data.done = distance, angle, done
        self.mover.publish_data()
        self.sent, self.sent_at = value, now
        if self.pose is None:
            return            # no status from a navigator that has no pose: its robot would read (0, 0, 0)
        nav = self.navigator.data
        nav.robot = Pose(*self.pose)
        goal = self.follower.goal
        nav.goal_set = goal is not None
        if goal is not None:
            nav.goal = Point(*goal)
        nav.autonomous = self.follower.active
        nav.stop_reason = self.stop_reason
        nav.plan = [Point(*goal)] if goal is not None else []
        self.navigator.publish_data()

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        now = time.monotonic()
        self._take_odometry(now)
        self._take_requests()
        if self.waiting is not None and self.pose is not None:
            self._goal(*self.waiting)
        stale = now - self.pose_at > EGO_STALE_S
        if self.follower.active and (self.brake or stale):
            self.follower.stop()
            self.stop_reason = STOP_OTHER
            self.logger.warn(f'{self.manager.name}: stopped: {"brake on" if self.brake else "no odometry"}')
        if self.follower.active:
            assert self.pose is not None        # a goal is set only once a pose came (_goal)
            out = self.follower.step(self.pose, *self.caps)
            if out.done:
                self.stop_reason = STOP_REACHED
            self._command(out.tv, out.rv)
            self.moving = True
            self._publish_state(now, out.tv, out.rv, out.distance, out.angle)
            return
        if self.moving:
            self._command(0.0, 0.0)              # one stop, then the base is left alone
            self.moving = False
        self._publish_state(now, 0.0, 0.0, 0.0, 0.0)

    def close(self) -> None:
        """Leave the robot stopped."""
        if self.moving:
            self._command(0.0, 0.0)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    program = os.path.basename(argv[0]) if argv else ''
    # The guide's chapter 1 names the program vectorMover and gives it a SynchroDrive (1.1.5).
    manager = CommsManager('VectorMover' if program == 'vectorMover' else 'SynchroMover')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'd:e:k:v:w:').user
    kind = user.get('k', 'synchro' if program == 'vectorMover' else 'robot')
    try:
        if kind not in ('robot', 'synchro'):
            raise ValueError(f'-k {kind!r}: robot or synchro')
        limits = MoverLimits(max_tv=float(user.get('v', MoverLimits.max_tv)),
                             max_rv=float(user.get('w', MoverLimits.max_rv)))
    except ValueError as error:
        print(f'synchro_mover: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = SynchroMover(manager, logger, limits, synchro=kind == 'synchro', drive=user.get('d'),
                          ego=user.get('e'))
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: moving by {"SynchroDrive" if kind == "synchro" else "RobotDrive"}; {limits}')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
