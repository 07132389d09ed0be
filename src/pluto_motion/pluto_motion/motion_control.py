"""The motionModule's control (Pluto 6.3), free of I/O: commands in, avoid requests and status codes
out.

* The thread: running from the start; a start_activity request starts it (and the avoid thread:
  "Starting the motion thread also starts the avoid thread"); a stop request stops it alone
  ("Stopping the motion thread does not stop the avoid thread"); cmdFlags -1 stops both.  While it
  is stopped (element[3] = -10) commands are ignored.
* cmdFlags < 40 pass through to the avoidModule and stop a running motion (it is kept: 44 with
  no values or 45 resume it).
* 42 moveto (on the map's plan, or by Pluto's ray following without a map or with ``rays_only``),
  43 investigate, 44 explore start a behaviour (:mod:`.motion_behaviours`); 46 sets or
  removes the rectangle.  Goals outside the rectangle are refused.
* element[2], element[3]: the behaviour's codes while it runs; when none runs element[3] is -1 with a
  rectangle set, 0 without, and element[2] keeps the last behaviour's outcome.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

from .active_scan import Aim, aim_for, is_wall_follow
from .grid_planner import Planner
from .motion_behaviours import (GOTO, GOTO_NORMAL, GOTO_REACHED, GOTO_STUCK, AvoidRequest, Explore, Investigate,
                                MotionSettings, Moveto, STOP, Situation, Step)
from .motion_command import (IDLE, IDLE_RECTANGLE, MOVETO_SET, NO_MOVETO, THREAD_STOPPED, CommandRefused, Kind,
                             MotionCommand, Rectangle)
from .planning_grid import PlanningGrid
from .ray_follow import RaySettings

__all__ = ['ANSWER_S', 'RESEND_S', 'MotionController']

#: Seconds after a new avoid request from which the avoid goto's state counts as its answer even
#: without a "goto normal" (-1) first.
ANSWER_S = 1.0
#: Seconds after which a goto the avoidModule has not answered is sent again: a request written
#: before the avoidModule's reader matched this writer (on a loaded machine, seconds after both
#: started) is lost, and nothing else would send it (investigate's goto hung so, r61).
RESEND_S = 1.0
Behaviour = Moveto | Investigate | Explore


class MotionController:
    """The motionModule's state.  :meth:`accept` takes a command, :meth:`step` runs the behaviour;
    both return the avoid requests to send (in order)."""

    def __init__(self, grid: PlanningGrid | None, settings: MotionSettings = MotionSettings(),
                 rays: RaySettings = RaySettings(), warn: Callable[[str], object] = print,
                 rays_only: bool = False) -> None:
        self.grid, self.settings, self.rays, self.warn = grid, settings, rays, warn
        #: moveto by ray following even with a map (Pluto 6.3's "42 moveto using ray_following").
        self.rays_only = rays_only
        #: A wrist is there (investigate's arm step turns it; :mod:`.active_scan`).
        self.wrist = False
        #: The avoidModule follows a wall at this module's command (the wrist turns left).
        self.wall_follow = False
        self.running = True
        self.rectangle: Rectangle | None = None
        self.behaviour: Behaviour | None = None
        self.paused: Behaviour | None = None
        self.element2 = NO_MOVETO
        self.motion_code: int | None = None           # element[3] of the running behaviour
        self.request: AvoidRequest | None = None
        self.sent_at = -math.inf
        self.resent_at = -math.inf
        self.answered = False
        self._planner: Planner | None = None
        #: Why the last moveto ended unreachable.
        self.reason = ''

    # -- status ----------------------------------------------------------------------------------
    @property
    def element3(self) -> int:
        if not self.running:
            return THREAD_STOPPED
        if self.behaviour is not None and self.motion_code is not None:
            return self.motion_code
        return IDLE_RECTANGLE if self.rectangle is not None else IDLE

    # -- commands --------------------------------------------------------------------------------
    def planner(self) -> Planner | None:
        """The planner over the map, restricted to the rectangle (None without a map)."""
        if self.grid is None:
            return None
        if self._planner is None:
            rectangle, near = self.rectangle, self.grid.resolution
            # A cell whose centre is within a cell of the rectangle counts as inside: a goal on its
            # border (explore's home, the middle of its base) lies in a cell whose centre may be
            # just outside, and would be unreachable.
            inside = None if rectangle is None else (lambda x, y: rectangle.contains(x, y, near))
            self._planner = Planner(self.grid.restricted(inside))
        return self._planner

    def inside(self, x: float, y: float) -> bool:
        """Whether a goal at (``x``, ``y``) is allowed: inside the rectangle, or anywhere without one.

        :param x: m, Localization/Pose frame.
        :param y: m, Localization/Pose frame.
        """
        return self.rectangle is None or bool(self.rectangle.contains(x, y))

    def moveto(self, goal: tuple[float, float]) -> Moveto:
        return Moveto(goal, None if self.rays_only else self.planner(), self.settings, self.rays)

    def start(self) -> None:
        """start_activity: the thread runs (a stopped behaviour stays stopped until resumed)."""
        self.running = True

    def accept(self, command: MotionCommand, pose: tuple[float, float, float] | None) -> list[AvoidRequest]:
        """Execute one command; the avoid requests it causes.

        :raises CommandRefused: a goal outside the rectangle; explore or investigate without a
            pose; a command while the thread is stopped.
        """
        kind = command.kind
        if kind is Kind.RELEASE:
            self._stop(keep=False)
            self.running, self.wall_follow = False, False
            return [AvoidRequest(-1)]
        if not self.running:
            raise CommandRefused(f'thread stopped: cmdFlags {command.cmd_flags} ignored (start_activity first)')
        if kind is Kind.PASS:
            self._stop(keep=True)
            self.wall_follow = is_wall_follow(command.cmd_flags)
            return [AvoidRequest(command.cmd_flags, command.position, command.velocity, command.force)]
        if kind is Kind.SET_RECTANGLE:
            self.rectangle, self._planner = command.rectangle, None
            return []
        if kind is Kind.RESUME:
            if self.behaviour is None and self.paused is not None:
                self.behaviour, self.paused = self.paused, None
                self.behaviour.resume()
                self.motion_code = None
            return []
        if kind is Kind.MOVETO:
            goal = (command.position[0], command.position[1])
            if not self.inside(*goal):
                raise CommandRefused(f'moveto ({goal[0]:.2f}, {goal[1]:.2f}) is outside the rectangle')
            self._begin(self.moveto(goal))
            # "element[2]=-1 if moveto point set (cmdFlags 42 received)" (Pluto 6.3): at once, so
            # that no status after the command still shows the last moveto's end.
            self.element2 = MOVETO_SET
            return []
        if pose is None:
            raise CommandRefused(f'cmdFlags {command.cmd_flags}: no pose yet')
        if kind is Kind.INVESTIGATE:
            self._begin(Investigate(self.settings, self.inside, self.warn, wrist=self.wrist))
            self.element2 = NO_MOVETO
            return []
        assert kind is Kind.EXPLORE and command.rectangle is not None
        self.rectangle = dataclasses.replace(command.rectangle, x=pose[0], y=pose[1], theta=pose[2])
        self._planner = None
        self._begin(Explore(self.rectangle, self.moveto, self.settings))
        self.element2 = NO_MOVETO
        return []

    def _begin(self, behaviour: Behaviour) -> None:
        self.behaviour, self.paused, self.motion_code = behaviour, None, None
        self.request, self.wall_follow = None, False

    def aim(self, pose: tuple[float, float, float] | None, now: float) -> Aim | None:
        """Where the wrist should look now (Pluto 4's active scanning); None: nowhere."""
        if not self.running and not self.wall_follow:
            return None
        return aim_for(self.behaviour, self.motion_code, self.element2, self.wall_follow, pose, now)

    def _stop(self, keep: bool) -> None:
        if self.behaviour is not None and keep:
            self.paused = self.behaviour
        self.behaviour, self.motion_code, self.request = None, None, None
        if not keep:
            self.paused = None

    # -- one loop --------------------------------------------------------------------------------
    def step(self, pose: tuple[float, float, float] | None, points, goto_state: int | None,
             now: float) -> list[AvoidRequest]:
        """Run the behaviour once; ``goto_state`` is element[1] of the newest avoid status."""
        if self.behaviour is None or not self.running or pose is None:
            return []
        if goto_state == GOTO_NORMAL:
            self.answered = True
        answer = goto_state if (self.answered or now - self.sent_at >= ANSWER_S) else None
        result: Step = self.behaviour.step(Situation(pose, points, answer, now))
        self.motion_code = result.element3
        if result.element2 or result.done:
            self.element2 = result.element2
        if result.done:
            if isinstance(self.behaviour, Moveto) and self.behaviour.reason:
                self.reason = self.behaviour.reason
                self.warn(f'moveto unreachable: {self.reason}')
            self.behaviour, self.motion_code, self.request = None, None, None
            return [STOP]                                           # the behaviour is over
        if result.request is not None and result.request != self.request:
            self.request, self.sent_at, self.answered = result.request, now, False
            return [result.request]
        if (self.request is not None and self.request.cmd_flags == GOTO and not self.answered
                and goto_state not in (GOTO_REACHED, GOTO_STUCK)
                and now - max(self.sent_at, self.resent_at) >= RESEND_S):
            self.resent_at = now
            return [self.request]
        return []
