"""What every module of the movement chain does the same way with its own two streams (Pluto 4: each
link "reads from its command interface (an ActuatorState_i) and writes to the next link's command
interface"; the status interface "a FVectorState_i" goes back up): judge each command request
(refused ones logged and counted), release on cmdFlags -1, ignore commands while the thread is
stopped, start and stop the thread on a status request (element[0] = 0 starts, -10 stops: the
proxies' start_activity), and publish the status on every change and once a second."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from wurde_core import CommsManager, Logger, Time
from wurde_core.interfaces import ActuatorState, FVectorState

from .drive_command import CommandRefused
from .drive_control import THREAD_STOPPED

__all__ = ['STATUS_PERIOD_S', 'THREAD_STOPPED', 'ChainLink']

#: Seconds between two publications of an unchanged status (a late reader must get one).
STATUS_PERIOD_S = 1.0


class ChainLink:
    """A link's command and status streams, registered as suppliers of ``manager``.

    :param parse: the request's (cmdFlags, velocity, position, force) to a command, None for a
        release; raises :class:`CommandRefused`.
    :param accept: executes an accepted command at ``now``.
    :param set_running: starts or stops the link's thread (called on changes only).
    :param running: whether the thread runs.
    """

    def __init__(self, manager: CommsManager, logger: Logger, command: str, status: str, *,
                 parse: Callable[[int, list[float], list[float], list[float]], Any],
                 accept: Callable[[Any, float], None], set_running: Callable[[bool], None],
                 running: Callable[[], bool]) -> None:
        self.manager, self.logger = manager, logger
        self.commands = ActuatorState(command)
        self.commands.set_queue_mode(True)          # every request is judged (and counted)
        self.status = FVectorState(status)
        manager.register_supplier(self.commands)
        manager.register_supplier(self.status)
        self._parse, self._accept, self._set, self._running = parse, accept, set_running, running
        self.refused = 0
        self.sent_status: tuple[list[float], list[int]] | None = None
        self.status_at = -math.inf

    def take_commands(self, now: float) -> list[int]:
        """Judge every command request; the element[0] values of the status requests taken in
        (0 and -10 already acted on), for a link that does more on them."""
        while self.commands.get_next_request():
            r = self.commands.requests
            flags = int(r.cmd_flags.get_value())
            try:
                command = self._parse(flags, list(r.velocity.get_value()), list(r.position.get_value()),
                                      list(r.force.get_value()))
            except CommandRefused as error:
                self.refused += 1
                self.logger.warn(f'{self.manager.name}: refused command ({self.refused} so far): {error}')
                continue
            if command is None:
                self.set_running(False, 'released (cmdFlags -1)')
            elif not self._running():
                self.logger.warn(f'{self.manager.name}: thread stopped; cmdFlags {flags} ignored '
                                 '(start_activity first)')
            else:
                self._accept(command, now)
        asked = []
        while self.status.get_next_request():
            element = list(self.status.requests.element.get_value())
            if element and element[0] in (0, THREAD_STOPPED):
                self.set_running(element[0] == 0, 'start_activity' if element[0] == 0 else 'stopped by request')
                asked.append(element[0])
        return asked

    def set_running(self, running: bool, why: str) -> None:
        if running != self._running():
            self._set(running)
            self.logger.notice(f'{self.manager.name}: thread {"started" if running else "stopped"}: {why}')

    def publish_status(self, data: Sequence[float], element: Sequence[int], now: float,
                       stamp: Time | None = None) -> None:
        """Publish when changed or :data:`STATUS_PERIOD_S` after the last publication; stamped
        ``stamp`` (the instant the loop computed it, as the ``now`` its rates used) or else at
        publication (a loaded machine can delay a publication past the next loop's start, and
        a ramp read from such stamps looks steeper than it was)."""
        value = ([float(v) for v in data], [int(e) for e in element])
        if value == self.sent_status and now - self.status_at < STATUS_PERIOD_S:
            return
        if stamp is not None:
            self.status.set_auto_timestamp(False)
            self.status.data.timestamp = stamp
        self.status.data.data, self.status.data.element = value
        self.status.publish_data()
        self.sent_status, self.status_at = value, now
