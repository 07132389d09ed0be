"""What every proxy of a movement chain link has in common (Pluto 4: "each link in the chain reads
from its command interface (an ActuatorState_i) ... For that the status interface is used (a
FVectorState_i)"): the command stream it writes requests to, the status stream it reads, the
start_activity and release_robot verbs, and waiting on the status with a deadline."""

from __future__ import annotations

import collections
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

from wurde_core import CommsManager
from wurde_core.interfaces import ActuatorState, FVectorState

from .drive_command import RELEASE
from .proxy import Proxy
from .task import Task, TaskResult

#: Seconds between sends of a goal command the link has not echoed yet.
RESEND_S = 1.0
#: Most resends of a command not echoed (a command of a kind the link does not echo).
MAX_RESENDS = 5
#: Statuses kept for update() when nobody asks (queue mode's cap).
UNREPORTED_MAX = 1000

__all__ = ['ChainProxy']


def _starts(values: Sequence[float], prefix: Sequence[float]) -> bool:
    """Whether ``values`` begins with ``prefix`` (to 1e-4: the echo went through float32 or not)."""
    return len(values) >= len(prefix) and all(math.isclose(a, b, abs_tol=1e-4) for a, b in zip(values, prefix))


class ChainProxy(Proxy):
    """A chain link as seen from ``manager``: requests on ``command``, status from ``status``."""

    def __init__(self, manager: CommsManager, command: str, status: str, *, queue_mode: bool = False) -> None:
        """Register the link's command and status streams.

        :param manager: the program's manager.
        :param command: the link's command stream (``drive/command``, ``avoidance/command``,
            ``motion/command``).
        :param status: the link's status stream (``drive/status`` ...).
        :param queue_mode: keep every status (:meth:`update` returns them all), not the newest,
            and every echo of an accepted command (``command.get_next_data()``)."""
        super().__init__(manager)
        self.command = ActuatorState(command)
        self.status = FVectorState(status)
        self.command.set_queue_mode(queue_mode)
        self.status.set_queue_mode(queue_mode)
        manager.register_consumer(self.command)
        manager.register_consumer(self.status)
        self.data: list[float] = []
        self.element: list[int] = []
        #: The stamp (s, the link's clock) of the newest status taken in.
        self.stamp = 0.0
        #: The link's newest echo of a command it accepted: (cmdFlags, position, stamp).
        self.echo: tuple[int, list[float], float] | None = None
        #: The newest command sent and not yet echoed: (cmdFlags, position + velocity, when it
        #: went, refusals then); see :meth:`_resend_unechoed`.
        self._unechoed: tuple[int, list[float], list[float], float, int] | None = None
        #: Resends of it so far (at most :data:`MAX_RESENDS`: a link that never echoes a command).
        self._resends = 0
        #: The newest echo's (cmdFlags, position, velocity).
        self._echoed: tuple[int, list[float], list[float]] | None = None
        #: Echoes taken in and not yet returned by echoes() (the newest 1000).
        self._unreported_echoes: collections.deque[Any] = collections.deque(maxlen=UNREPORTED_MAX)
        #: Statuses taken in and not yet returned by update() (the newest 1000, as a queue).
        self._unreported: collections.deque[Any] = collections.deque(maxlen=UNREPORTED_MAX)

    def _send(self, flags: int, velocity: Sequence[float], position: Sequence[float],
              force: Sequence[float] = ()) -> bool:
        req = self.command.requests
        req.cmd_flags.set_value(flags)
        req.velocity.set_value(list(velocity))
        req.position.set_value(list(position))
        req.force.set_value(list(force))
        self._unechoed = (flags, list(position), list(velocity), time.monotonic(), self.refused)
        self._resends = 0
        return self._request(self.command)

    def _resend_unechoed(self) -> None:
        """Send the newest command again every :data:`RESEND_S` until the link echoes it or says it
        refused one: a writer matched to the link's reader is not yet a reader matched to the
        writer (discovery runs both ways, not at once), and a request published in between is lost
        (on a loaded machine a command sent once can fail to reach the link).  The goal tasks'
        handshake, for every command."""
        pending = self._unechoed
        if pending is None:
            return
        flags, position, velocity, sent, refused = pending
        echo = self._echoed
        if echo is not None and echo[0] == flags and _starts(echo[1], position) and _starts(echo[2], velocity):
            self._unechoed = None
        elif self.refused > refused or self._resends >= MAX_RESENDS:
            self._unechoed = None
        elif time.monotonic() - sent > RESEND_S and self.command not in self._held:
            self.command.publish_request()
            self._resends += 1
            self._unechoed = (flags, position, velocity, time.monotonic(), refused)

    def _take_echoes(self) -> None:
        while self.command.get_next_data():
            d = self.command.data
            self.echo = (int(d.cmd_flags), [float(v) for v in [*d.position, *d.velocity]],
                         d.timestamp.get_seconds())
            self._echoed = (int(d.cmd_flags), [float(v) for v in d.position], [float(v) for v in d.velocity])
            self._unreported_echoes.append(d.ros_message())

    def echoes(self) -> list[Any]:
        """The link's echoes of the commands it accepted (its ``command`` data), taken in since the
        last call, oldest first: the proxy reads them for its own handshake, so a program that
        wants them asks here rather than reading the channel."""
        self._take_echoes()
        taken = list(self._unreported_echoes)
        self._unreported_echoes.clear()
        return taken

    def _goal_task(self, flags: int, key: Sequence[float], send: Callable[[], object],
                   outcome: Callable[[], tuple[TaskResult, str]], what: str, timeout: float | None,
                   spin: bool = True) -> Task:
        """The handle of a goal command (goto, moveto to x, y; explore of b, h — ``key``, the
        first numbers of the command's position then velocity): ``send`` it, again every
        :data:`RESEND_S` until the link echoes it (a request sent before discovery matched is
        lost); then only a status stamped after the echo counts, so that the last goal's end is
        never taken for this one's, and ``outcome()`` judges it.  ``spin``: each poll runs a turn
        of the manager's loop (a client's loop); False for a module whose own loop runs it."""
        refused = self.refused
        sent = -math.inf
        echoed: float | None = None

        def resend() -> None:
            nonlocal sent
            send()
            sent = time.monotonic()

        def poll() -> tuple[TaskResult, str]:
            nonlocal echoed
            if spin:
                self.spin_once(0.05)
            self._exchange()
            self._take_echoes()
            if self.refused > refused:
                return TaskResult.FAILED, f'{what} refused (see the module log)'
            if echoed is None:
                e = self.echo
                if e is not None and e[0] == flags and len(e[1]) >= len(key) and all(
                        math.isclose(a, b, abs_tol=1e-4) for a, b in zip(e[1], key)):
                    echoed = e[2]
                elif time.monotonic() - sent > RESEND_S:
                    resend()
                return TaskResult.UNKNOWN, ''
            if self.stamp < echoed:
                return TaskResult.UNKNOWN, ''
            return outcome()

        self._take_echoes()
        self.echo = None
        resend()
        return Task(poll, self.stop, timeout=timeout)

    @property
    def refused(self) -> int:
        """Commands the link refused so far (0 before a status says)."""
        return 0

    def send(self, cmd_flags: int, velocity: Sequence[float] = (), position: Sequence[float] = (),
             force: Sequence[float] = ()) -> bool:
        """Any command of the link, as written (held and sent again as every command; see
        :meth:`_request` and :meth:`_resend_unechoed`).

        :param cmd_flags: the link's cmdFlags (Pluto 6: the driveModule's, avoidModule's or
            motionModule's).
        :param velocity: the ActuatorState velocity array ([] for none).
        :param position: the position array ([] for none).
        :param force: the force array ([] for none).
        :returns: whether it went now (False: held until the link's reader is matched).
        """
        return self._send(cmd_flags, list(velocity), list(position), list(force))

    def stop(self) -> bool:
        """Stop the robot (a velocity 0)."""
        return self._send(0, [0.0, 0.0], [])

    def release_robot(self) -> bool:
        """Stop the link's thread (cmdFlags -1): it stops the robot once and then leaves it alone."""
        return self._send(RELEASE, [], [])

    def start_activity(self) -> bool:
        """Start the link's thread and the ones below it (nothing happens to a running one)."""
        self.status.requests.element.set_value([0])
        return self._request(self.status)

    def update(self) -> list[Any]:
        """Send held requests whose reader is matched now; take in what arrived; the status
        messages taken in since the last call, oldest first (empty: none) — also those a task's
        poll took in meanwhile."""
        self._exchange()
        taken = list(self._unreported)
        self._unreported.clear()
        return taken

    def _exchange(self) -> None:
        """Send held requests whose reader is matched now; take in the statuses for :meth:`update`
        to report (a task's poll must not swallow them: a caller that lists them saw a goto end
        without its final status)."""
        self._send_held()
        while self.status.get_next_data():
            self.data, self.element = list(self.status.data.data), list(self.status.data.element)
            self.stamp = self.status.data.timestamp.get_seconds()
            self._unreported.append(self.status.data.ros_message())
        self._take_echoes()
        self._resend_unechoed()

    @property
    def velocities(self) -> tuple[float, float] | None:
        """data[0..1]: the (slowed-down) linear and angular velocity commanded now."""
        return (self.data[0], self.data[1]) if len(self.data) >= 2 else None

    @property
    def code(self) -> int | None:
        """element[0] (None before the first status)."""
        return self.element[0] if self.element else None
