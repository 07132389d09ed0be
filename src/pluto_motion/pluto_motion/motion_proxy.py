"""MotionProxy: Pluto's motion proxy (Pluto 5) for WURDE programs, with a nav2_simple_commander-like
``go_to`` on top.

Verbs write ``motion/command`` (Pluto 6.3's cmdFlags: 42 moveto, 43 investigate, 44 explore, 45
resume, 46 set the rectangle, -1 release; anything below 40 goes on to the avoidModule) or the
status request that starts the threads; accessors read ``motion/status``.

``go_to(x, y)`` sends a moveto (``explore_task(b, h)`` an explore) and returns a
:class:`pluto_motion.task.Task`: SUCCEEDED when
element[2] = 1 (at goal), FAILED when it is 3 (unreachable on the map), when the motion thread
stops, the command is refused or the deadline passes, CANCELED after ``cancel()`` (which stops
the robot).  Only a status stamped after the motionModule's echo of this very moveto counts.
"""

from __future__ import annotations

from wurde_core import CommsManager

from .chain_proxy import ChainProxy
from .motion_command import (AT_GOAL, COMMAND, IDLE, IDLE_RECTANGLE, NO_MOVETO, STATUS, THREAD_STOPPED,
                             UNREACHABLE)
from .task import Task, TaskResult

__all__ = ['MotionProxy']


class MotionProxy(ChainProxy):
    """The motionModule as seen from ``manager``: ``moveto_status`` is element[2], ``motion_status``
    element[3], ``code`` and ``goto_status`` element[0..1] (the avoidModule's).  ``send`` with
    cmdFlags below 40 goes on to the avoidModule (and stops a running motion)."""

    def __init__(self, manager: CommsManager, *, queue_mode: bool = False) -> None:
        """Register ``motion/command`` and ``motion/status`` with ``manager``.

        :param manager: the program's manager.
        :param queue_mode: keep every status and echo (:meth:`update` returns them all), not the
            newest.
        """
        super().__init__(manager, COMMAND, STATUS, queue_mode=queue_mode)

    # -- the seed's verbs ------------------------------------------------------------------------
    def moveto(self, x: float, y: float) -> bool:
        """Move to (``x``, ``y``) (m, Localization/Pose frame): planned on the module's map, or
        ray following without one (cmdFlags 42).

        :param x: the goal's x (m, Localization/Pose frame).
        :param y: the goal's y (m, Localization/Pose frame).
        :returns: whether it went now (False: held until the motionModule reads commands).
        """
        return self._send(42, [], [x, y])

    def investigate(self) -> bool:
        """Go to the closest object and circle it (cmdFlags 43)."""
        return self._send(43, [], [])

    def explore(self, b: float, h: float) -> bool:
        """Explore the rectangle b, h whose home is the current pose (cmdFlags 44).

        :param b: the distance from home to each side beside it (m): the base is 2 b long.
        :param h: the rectangle's height (m), along the robot's heading.
        :returns: whether it went now (False: held until the motionModule reads commands).
        """
        return self._send(44, [b, h], [])

    def resume(self) -> bool:
        """Resume the stopped explore / moveto / investigate (cmdFlags 45)."""
        return self._send(45, [], [])

    def set_rectangle(self, b: float, h: float, x: float = 0.0, y: float = 0.0, theta: float = 0.0) -> bool:
        """Set the rectangle (home x, y, theta; Pluto 6.3's geometry); b = 0 removes it (cmdFlags 46).

        :param b: the distance from home to each side beside it (m): the base is 2 b long; 0
            removes the rectangle.
        :param h: the height (m), from the base along ``theta``.
        :param x: home's x, the middle of the base (m, Localization/Pose frame).
        :param y: home's y (m).
        :param theta: the direction into the rectangle, perpendicular to the base (rad).
        :returns: whether it went now (False: held until the motionModule reads commands).
        """
        return self._send(46, [b, h], [x, y], [theta])

    def stop(self) -> bool:
        """Stop the robot (a velocity 0 through avoid): the motion stops and can be resumed."""
        return self._send(0, [0.0, 0.0], [])

    # -- status ----------------------------------------------------------------------------------
    @property
    def goto_status(self) -> int | None:
        return self.element[1] if len(self.element) > 1 else None

    @property
    def moveto_status(self) -> int | None:
        """element[2]: -1 moveto set, -2 nearing, 1 at goal, 2 investigate done, 3 unreachable, 4 blocked
        (waiting for the way to clear), 0."""
        return self.element[2] if len(self.element) > 2 else None

    @property
    def motion_status(self) -> int | None:
        """element[3]: -10 stopped, -1 idle with rectangle, 0 idle, 1 scanning, 3 following, 11, 12."""
        return self.element[3] if len(self.element) > 3 else None

    @property
    def refused(self) -> int:
        """data[2] (ours): commands the motionModule refused so far."""
        return int(self.data[2]) if len(self.data) > 2 else 0

    def go_to(self, x: float, y: float, *, timeout: float | None = None, spin: bool = True) -> Task:
        """Start a moveto and return its handle (``spin`` False: polling it does not run the
        manager's loop, for a module whose own loop does).

        :param x: the goal's x (m, Localization/Pose frame).
        :param y: the goal's y (m, Localization/Pose frame).
        :param timeout: how long the task may take before it fails (s); None: no limit.
        :param spin: whether polling the task runs a turn of the manager's loop.
        """
        def outcome() -> tuple[TaskResult, str]:
            if self.motion_status == THREAD_STOPPED:
                return TaskResult.FAILED, 'motion thread stopped'
            if self.moveto_status == NO_MOVETO and self.motion_status in (IDLE, IDLE_RECTANGLE):
                # after the echo of this moveto element[2] is never 0 again in the same process
                return TaskResult.FAILED, 'the motionModule holds no moveto (restarted)'
            ends: dict[int | None, tuple[TaskResult, str]] = {AT_GOAL: (TaskResult.SUCCEEDED, ''),
                                                               UNREACHABLE: (TaskResult.FAILED, 'unreachable')}
            return ends.get(self.moveto_status, (TaskResult.UNKNOWN, ''))

        return self._goal_task(42, (x, y), lambda: self.moveto(x, y), outcome, 'moveto', timeout, spin)

    def explore_task(self, b: float, h: float, *, timeout: float | None = None, spin: bool = True) -> Task:
        """Start an explore of the rectangle b, h whose home is the current pose and return its
        handle: SUCCEEDED when the robot is home again (element[2] = 1; points a plan finds
        unreachable are skipped, Pluto 6.3), FAILED when the motion thread stops.  The explore's
        rectangle stays the limit of later goals until ``set_rectangle(0, 0)`` removes it.  FAILED
        too when the way home is unreachable (element[2] = 3 at the end).

        :param b: the distance from home to each side beside it (m): the base is 2 b long.
        :param h: the rectangle's height (m), along the robot's heading.
        :param timeout: how long the task may take before it fails (s); None: no limit.
        :param spin: whether polling the task runs a turn of the manager's loop.
        """
        def outcome() -> tuple[TaskResult, str]:
            if self.motion_status == THREAD_STOPPED:
                return TaskResult.FAILED, 'motion thread stopped'
            ends: dict[int | None, tuple[TaskResult, str]] = {AT_GOAL: (TaskResult.SUCCEEDED, ''),
                                                               UNREACHABLE: (TaskResult.FAILED, 'home unreachable')}
            return ends.get(self.moveto_status, (TaskResult.UNKNOWN, ''))

        return self._goal_task(44, (b, h), lambda: self.explore(b, h), outcome, 'explore', timeout, spin)
