"""``navigator``: CARMEN's navigator (Programming with CARMEN 4.2.1, 4.3) on the Pluto chain.

    navigator [-m MAP] [-s STREAM] [-t SECONDS] [-b BASE]

Supplies NavigatorTransport on ``STREAM`` (default ``Navigator``; consumers use
:class:`wurde_core.wrappers.Navigator`): one goal at a time in the map frame, a point or a place of
the map (an unknown place is a warning, 4.2.1); ``go`` drives to it by the motionModule's moveto,
``stop`` stops the robot.  The status carries the Localization/Pose, the goal, whether it is
autonomous and 4.3's autonomous-stopped reason: 1 goal reached, 2 user stopped, 3 (ours) not
reached — unreachable, refused, more than ``-t`` seconds, or the base down.

A goal survives the chain (issue 38): a moveto that fails otherwise (the motion thread stopped, a
link restarted) is sent again after :data:`RETRY_S`, and a restarted navigator resumes its goal
from its resume file.  The base is down when its odometry (``<BASE>Motion``) is silent for the
tunable ``base_wait``, or :data:`FIRST_SAMPLE_S` before a first sample; a chain failure while the
base is quiet (:data:`BASE_QUIET_S`) is judged once the base is down or heard again, so that the
log names the cause.  docs/carmen.md ("CARMEN's navigator") has the whole behaviour.
"""

from __future__ import annotations

import math
import sys
import time

from wurde_core import CommsManager, Logger, Point, Pose, RunState
from wurde_core.interfaces import Egomotion, robot_object_class
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_core.resume import ResumeState
from wurde_core.wrappers import GOAL_REACHED, STOP_FAILED, STOP_NONE, USER_STOPPED
from wurde_idl.errors import ConfigError
from wurde_idl.maps import load_map

from pluto_nav.loc_proxy import LocProxy
from pluto_nav.streams import POSE

from .motion_proxy import MotionProxy
from .task import Task, TaskResult

__all__ = ['AT_GOAL_M', 'BASE_WAIT_S', 'FIRST_SAMPLE_S', 'FINAL_FAILURES', 'RETRY_S', 'NavigatorModule', 'main']

LOOP_S = 0.05
STATUS_PERIOD_S = 0.5
#: A robot this near its goal (m) is at it: ``go`` then ends at once with goal reached (the
#: motionModule's own reach is 0.25 m).  The default of the tunable ``approach_dist``.
AT_GOAL_M = 0.3
#: Seconds of silence of the base's odometry after which it is down (the default of ``base_wait``):
#: several times the MCP's default TTL, so that a critical base the MCP notices and restarts
#: idles the navigator before it counts as down.
BASE_WAIT_S = 5.0
#: Seconds allowed for the first sample after the navigator's start or return to Run: the base
#: (a new process, after a restart) must be discovered first, which on a loaded machine can take
#: seconds.  Until then a silent base is down only after the longer of this and ``base_wait``.
FIRST_SAMPLE_S = 20.0
#: Seconds of silence of the base's odometry after which a failure of the chain is not judged at
#: once: a chain whose base died may fail first (its pose stale, its goto stuck, its plan
#: unreachable), and that failure's reason would hide the cause.  Many odometry periods long.
BASE_QUIET_S = 1.0
#: The chain failures that end a goal: the map says it cannot be reached, or the motionModule
#: refused it.  Any other (the motion thread stopped, a link restarted) is the chain's hiccup: the
#: goal is sent again after :data:`RETRY_S`, until the goal's own time (``-t``) is up.
FINAL_FAILURES = ('unreachable', 'moveto refused (see the module log)')
RETRY_S = 1.0
HELP = ('  -m MAP       the map whose places set_goal_place names (default map.xml of the config directory)\n'
        '  -s STREAM    the NavigatorTransport stream supplied (default Navigator)\n'
        '  -t SECONDS   longest drive to one goal (default 300)\n'
        '  -b BASE      the base whose odometry (<BASE>Motion) says it is up (default PlutoBase)')


class NavigatorModule:
    """The navigator's state and its loop step."""

    def __init__(self, manager: CommsManager, logger: Logger, places: dict, stream: str, timeout: float,
                 base: str = 'PlutoBase') -> None:
        self.manager = manager
        self.logger = logger
        self.places = places
        self.timeout = timeout
        self.approach = manager.tunable(
            'approach_dist', AT_GOAL_M, 'm: go this near the goal ends at once with goal reached '
            '(CARMEN 4.3\'s navigator_approach_dist)', 0.01, 5.0)
        self.nav = robot_object_class('NavigatorTransport')(stream)
        self.nav.set_queue_mode(True)       # set_goal_place then go: two requests, neither lost
        manager.register_supplier(self.nav)
        self.base_wait = manager.tunable(
            'base_wait', BASE_WAIT_S, 's: the base\'s odometry silent this long, the base is down and a '
            'goal fails', 0.5, 600.0)
        self.motion = MotionProxy(manager)
        self.loc = LocProxy(manager, 1 << POSE)
        self.base = base
        self.odometry = Egomotion(f'{base}Motion')
        manager.register_consumer(self.odometry)
        self._odometry_at = time.monotonic()    # the last sample, or the start / return to Run
        self._heard = False                     # a sample since the start / return to Run
        manager.on_state(RunState.RUN, self._resumed)
        self.goal: tuple[float, float] | None = None
        self.autonomous = False
        self.stop_reason = STOP_NONE
        self.task: Task | None = None
        self._held: str | None = None       # the reason of a chain failure while the base is quiet
        self._sent: tuple | None = None
        self._sent_at = -math.inf
        self._deadline = math.inf           # when the goal being driven to has had its -t seconds
        self._retry_at: float | None = None  # when a goal whose chain failed is sent again
        self.retries = 0
        self.resume = ResumeState()
        self._resume_goal()

    def _resume_goal(self) -> None:
        """A restarted navigator picks up the goal its last process held (and drives to it again
        if it was autonomous): a goal survives the navigator's own restart."""
        state, why = self.resume.load()
        if state is None:
            return
        goal, left = state.get('goal'), state.get('left_s')
        if isinstance(goal, list) and len(goal) == 2 and all(isinstance(v, (int, float)) for v in goal):
            self.goal = (float(goal[0]), float(goal[1]))
        if self.goal is not None and state.get('autonomous') is True:
            self.autonomous = True
            remaining = float(left) if isinstance(left, (int, float)) and left > 0 else self.timeout
            self._deadline = time.monotonic() + remaining
            self._retry_at = time.monotonic()        # driven to from the first step
            self._say(f'resuming the goal {self.goal} ({why}; {remaining:.0f} s of its time left)')

    def _keep(self, force: bool = True) -> None:
        """The goal, whether it is being driven to and the time it has left, in the resume file
        (:meth:`_resume_goal`): at once on a change (``force``), else at most every half second."""
        left = self._deadline - time.monotonic() if self.autonomous else None
        self.resume.save({'goal': list(self.goal) if self.goal is not None else None,
                          'autonomous': self.autonomous,
                          'left_s': left if left is not None and math.isfinite(left) else None},
                         force=force)

    @property
    def robot(self) -> tuple[float, float, float] | None:
        pose = self.loc.get_pose(POSE)
        return None if pose is None else (pose.pose[0], pose.pose[1], pose.pose[3])

    def _say(self, text: str) -> None:
        self.logger.notice(f'{self.manager.name}: {text}')

    def _requests(self) -> None:
        while self.nav.get_next_request():
            r = self.nav.requests
            written = set(r.ros_message().set_fields)
            place = str(r.goal_place.get_value()) if 'goal_place' in written else ''
            if place:
                if place in self.places:
                    p = self.places[place]
                    self._set_goal(p.x, p.y, f'place {place}')
                else:
                    self.logger.warn(f'{self.manager.name}: no place {place!r} on the map; the goal '
                                     f'is unchanged (places: {", ".join(self.places)})')
            elif 'goal' in written:
                g = r.goal.get_value()
                self._set_goal(g.x(), g.y(), f'({g.x():.2f}, {g.y():.2f})')
            if 'autonomous' in written:
                self._go() if bool(r.autonomous.get_value()) else self._stop()

    def _set_goal(self, x: float, y: float, what: str) -> None:
        if not (math.isfinite(x) and math.isfinite(y)):
            self.logger.warn(f'{self.manager.name}: goal {what} refused: not finite')
            return
        self.goal = (x, y)
        self._say(f'goal {what}')
        if self.autonomous:
            self._deadline = time.monotonic() + self.timeout
            self._drive()
        else:
            self._keep()

    def _go(self) -> None:
        if self.goal is None:
            self.logger.warn(f'{self.manager.name}: go without a goal: nothing to do')
            return
        robot = self.robot
        if robot is not None and math.dist(robot[:2], self.goal) < self.approach.value:
            self.autonomous, self.stop_reason = True, STOP_NONE     # momentarily autonomous (4.3)
            self._publish(force=True)
            self._end(GOAL_REACHED, 'already at the goal')
            return
        self.autonomous, self.stop_reason = True, STOP_NONE
        self._deadline = time.monotonic() + self.timeout
        silent = self._base_down()
        if silent is not None:
            self._base_failed(silent)
            return
        self._drive()

    def _drive(self) -> None:
        assert self.goal is not None
        self._held, self._retry_at = None, None
        self.motion.start_activity()            # the chain's threads (nothing happens to running ones)
        left = max(self._deadline - time.monotonic(), 0.0)
        self.task = self.motion.go_to(*self.goal, timeout=left, spin=False)
        self._keep()

    def _stop(self) -> None:
        if self.task is not None:
            self.task.cancel()
            self.task = None
        self._end(USER_STOPPED, 'stopped by the user')

    def _end(self, reason: int, why: str) -> None:
        self.autonomous, self.stop_reason, self.task, self._held = False, reason, None, None
        self._retry_at, self._deadline = None, math.inf
        self._keep()
        self._say(f'autonomous stopped: {why}')
        self._publish(force=True)

    def _publish(self, force: bool = False) -> None:
        robot = self.robot
        goal = self.goal or (0.0, 0.0)
        state = (robot, self.goal, self.autonomous, self.stop_reason)
        now = time.monotonic()
        if not force and state == self._sent and now - self._sent_at < STATUS_PERIOD_S:
            return
        d = self.nav.data
        d.robot = Pose(*(robot or (0.0, 0.0, 0.0)))
        d.goal = Point(*goal)
        d.goal_set = self.goal is not None
        d.autonomous = self.autonomous
        d.stop_reason = self.stop_reason
        d.plan = []
        if self.nav.publish_data():
            self._sent, self._sent_at = state, now

    def _resumed(self) -> None:
        """Back in Run after Idle (under the MCP: the critical base is back, maybe as a new
        process): the silence counts from now, not from before the Idle."""
        self._odometry_at, self._heard = time.monotonic(), False

    def _base_down(self) -> float | None:
        """Seconds the base's odometry has been silent, when that makes the base down."""
        now = time.monotonic()
        if self.odometry.get_next_data():
            self._odometry_at, self._heard = now, True
        silent = now - self._odometry_at
        limit = self.base_wait.value if self._heard else max(self.base_wait.value, FIRST_SAMPLE_S)
        return silent if silent > limit else None

    def _base_failed(self, silent: float) -> None:
        if self.task is not None:
            self.task.cancel()              # the chain stops: nothing drives on when the base is back
        self._failed(f'the base is down: no odometry from {self.base} for {silent:.1f} s')

    def step(self) -> None:
        self.motion.update()
        self._requests()
        silent = self._base_down()
        if self.autonomous and silent is not None:
            self._base_failed(silent)
        if self.task is not None and self.task.is_task_complete():
            result = self.task.result()
            if result is TaskResult.SUCCEEDED:
                self._end(GOAL_REACHED, 'goal reached')
            elif result is TaskResult.FAILED:
                if time.monotonic() - self._odometry_at > BASE_QUIET_S:
                    self._held, self.task = self.task.reason, None      # judged when the base says
                else:
                    self._chain_failed(self.task.reason)
        elif self._held is not None and time.monotonic() - self._odometry_at <= BASE_QUIET_S:
            self._chain_failed(self._held)          # the base is up: the chain's reason stands
        elif self._retry_at is not None and self.autonomous and time.monotonic() >= self._retry_at:
            if time.monotonic() >= self._deadline:
                self._failed(f'not reached within {self.timeout:g} s')
            else:
                self._drive()
        if self.autonomous:
            self._keep(force=False)
        self._publish()

    def _chain_failed(self, why: str) -> None:
        """The moveto failed: a final failure (:data:`FINAL_FAILURES`, the goal's time up) ends
        the goal; any other is a link of the chain that stopped or restarted, and the goal is sent
        again — the status stays autonomous, neither reached nor failed."""
        self._held, self.task = None, None
        if why in FINAL_FAILURES or why == 'timed out' or time.monotonic() >= self._deadline:
            self._failed(why if why != 'timed out' else f'not reached within {self.timeout:g} s')
            return
        self.retries += 1
        self._retry_at = time.monotonic() + RETRY_S
        self.logger.warn(f'{self.manager.name}: the chain lost the goal {self.goal} ({why}); sending it '
                         f'again in {RETRY_S:g} s (retry {self.retries})')

    def _failed(self, why: str) -> None:
        self.logger.warn(f'{self.manager.name}: goal {self.goal} not reached: {why}')
        self._end(STOP_FAILED, why)

    def close(self) -> None:
        """Leave the robot stopped when the navigator goes while driving."""
        if self.autonomous:
            self.motion.stop()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('navigator')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'm:s:t:b:').user
    try:
        world = load_map(config_file(manager, opts.get('m'), 'map.xml'))
        timeout = float(opts.get('t', 300.0))
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        print(f'navigator: -t: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = NavigatorModule(manager, logger, dict(world.places), opts.get('s', 'Navigator'), timeout,
                             opts.get('b', 'PlutoBase'))
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: supplying {module.nav.stream}; {len(world.places)} places on {world.name}')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
