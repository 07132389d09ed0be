"""AvoidProxy: Pluto's avoid proxy (Pluto 5) for WURDE programs, with a nav2_simple_commander-like
``go_to`` on top.

Verbs write ``avoidance/command`` (cmdFlags 10*A+T, Pluto 6.2: the keyword arguments ``sonar`` and
``laser`` make A) or the status request that starts the threads (start_activity starts the avoid
thread and, through it, the drive's); accessors read ``avoidance/status``.

``go_to(x, y)`` sends a goto and returns a :class:`pluto_motion.task.Task`: SUCCEEDED when
element[1] says the point is reached, FAILED when the goto is stuck, the avoid thread stops, the
command is refused or the deadline passes, CANCELED after ``cancel()`` (which stops the robot).
Only a status stamped after the avoidModule's echo of this very goto counts, so the result of an
earlier goto is never taken for this one's.
"""

from __future__ import annotations

from wurde_core import CommsManager

from .avoid_command import COMMAND, STATUS, Kind
from .avoid_control import GOTO_REACHED, GOTO_STUCK, THREAD_STOPPED
from .chain_proxy import ChainProxy
from .task import Task, TaskResult

__all__ = ['AvoidProxy']


def _flags(kind: Kind, sonar: bool, laser: bool) -> int:
    return 10 * (int(sonar) + 2 * int(laser)) + int(kind)


class AvoidProxy(ChainProxy):
    """The avoidModule as seen from ``manager``.

    ``code`` is element[0] (the drive's, or 6 laser slow/stop, 7 laser dead); ``goto_status`` is
    element[1] (1 reached, 2 stuck, -1 goto normal, -10 thread stopped, 0 otherwise).
    """

    def __init__(self, manager: CommsManager, *, queue_mode: bool = False) -> None:
        """Register ``avoidance/command`` and ``avoidance/status`` with ``manager``.

        :param manager: the program's manager.
        :param queue_mode: keep every status and echo (:meth:`update` returns them all), not the
            newest.
        """
        super().__init__(manager, COMMAND, STATUS, queue_mode=queue_mode)

    # -- the seed's verbs ------------------------------------------------------------------------
    def velocity(self, tv: float, rv: float, *, sonar: bool = False, laser: bool = False) -> bool:
        """Drive at ``tv`` m/s and ``rv`` rad/s (T = 0).

        :param tv: the linear velocity (m/s).
        :param rv: the angular velocity (rad/s).
        :param sonar: protect by the sonar (A + 1).
        :param laser: protect by the laser (A + 2).
        :returns: whether it went now (False: held until the avoidModule reads commands).
        """
        return self._send(_flags(Kind.VELOCITY, sonar, laser), [tv, rv], [])

    def regulator(self, speed: float, heading: float, *, sonar: bool = False, laser: bool = False) -> bool:
        """Turn to ``heading`` (rad, Localization/Pose frame) and hold it at ``speed`` m/s (T = 1).

        :param speed: the linear speed (m/s).
        :param heading: the heading (rad, Localization/Pose frame).
        :param sonar: protect by the sonar (A + 1).
        :param laser: protect by the laser (A + 2).
        :returns: whether it went now (False: held until the avoidModule reads commands).
        """
        return self._send(_flags(Kind.REGULATOR, sonar, laser), [speed], [0.0, heading])

    def goto(self, x: float, y: float, max_tv: float = 0.5, max_rv: float = 1.0, *, strength: float = 1.0,
             sonar: bool = True, laser: bool = True) -> bool:
        """Go to (``x``, ``y``) (m, Localization/Pose frame) round near obstacles, at most ``max_tv``
        m/s and ``max_rv`` rad/s; ``strength`` > 1 weakens the avoidance (T = 2).

        :param x: the goal's x (m, Localization/Pose frame).
        :param y: the goal's y (m, Localization/Pose frame).
        :param max_tv: the most linear speed (m/s).
        :param max_rv: the most angular speed (rad/s).
        :param strength: the goal's pull, force[0]: 1 by default, above 1 the goal wins over the
            obstacles, below 1 the obstacles win.
        :param sonar: avoid what the sonar sees (A + 1).
        :param laser: avoid what the laser sees (A + 2).
        :returns: whether it went now (False: held until the avoidModule reads commands).
        """
        return self._send(_flags(Kind.GOTO, sonar, laser), [max_tv, max_rv], [x, y], [strength])

    def wall_follow(self, speed: float, distance: float = 0.0, *, sonar: bool = False, laser: bool = True) -> bool:
        """Follow the wall on the left at ``speed`` m/s, the camera ``distance`` m from it (0: the
        module's default) (T = 3).

        :param speed: the linear speed (m/s).
        :param distance: the camera's distance from the wall (m); 0: the module's own (0.8 m).
        :param sonar: protect by the sonar (A + 1).
        :param laser: protect by the laser (A + 2); the wall follow needs the laser whatever it is.
        :returns: whether it went now (False: held until the avoidModule reads commands).
        """
        return self._send(_flags(Kind.WALL_FOLLOW, sonar, laser), [speed], [distance, 0.0])

    def stop(self) -> bool:
        return self.velocity(0.0, 0.0)

    # -- status ----------------------------------------------------------------------------------
    @property
    def goto_status(self) -> int | None:
        """element[1] (None before the first status)."""
        return self.element[1] if len(self.element) > 1 else None

    @property
    def refused(self) -> int:
        """element[2] (ours): commands the avoidModule refused so far."""
        return self.element[2] if len(self.element) > 2 else 0

    # -- nav2-like layer -------------------------------------------------------------------------
    def go_to(self, x: float, y: float, max_tv: float = 0.5, max_rv: float = 1.0, *, strength: float = 1.0,
              sonar: bool = True, laser: bool = True, timeout: float | None = None) -> Task:
        """Start a goto (default cmdFlags 32) and return its handle.

        :param x: the goal's x (m, Localization/Pose frame).
        :param y: the goal's y (m, Localization/Pose frame).
        :param max_tv: the most linear speed (m/s).
        :param max_rv: the most angular speed (rad/s).
        :param strength: the goal's pull (:meth:`goto`).
        :param sonar: avoid what the sonar sees.
        :param laser: avoid what the laser sees.
        :param timeout: how long the task may take before it fails (s); None: no limit.
        :returns: the task: SUCCEEDED when the point is reached, FAILED when the goto is stuck,
            the avoid thread stops, the command is refused or the deadline passes, CANCELED after
            ``cancel()``.
        """
        def outcome() -> tuple[TaskResult, str]:
            ends: dict[int | None, tuple[TaskResult, str]] = {
                GOTO_REACHED: (TaskResult.SUCCEEDED, ''), GOTO_STUCK: (TaskResult.FAILED, 'goto stuck'),
                THREAD_STOPPED: (TaskResult.FAILED, 'avoid thread stopped')}
            return ends.get(self.goto_status, (TaskResult.UNKNOWN, ''))

        return self._goal_task(_flags(Kind.GOTO, sonar, laser), (x, y),
                               lambda: self.goto(x, y, max_tv, max_rv, strength=strength, sonar=sonar, laser=laser),
                               outcome, 'goto', timeout)
