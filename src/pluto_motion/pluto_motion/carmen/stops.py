"""The navigator's autonomous-stopped events (Programming with CARMEN 4.3) from its statuses.

Our navigator has no separate message: its status says ``autonomous`` and ``stop_reason`` (1 goal
reached, 2 user stopped, 3 not reached), and goes out on every change and every 0.5 s.  A stop is
a status not autonomous with a reason after one that was autonomous or had another reason (read
in queue mode, so that ``go`` at the goal — autonomous for one status — is seen).  A ``stop``
this program sent while the navigator already stood with reason 2 changes nothing in the status:
the first status stamped after it is that stop (4.3: every stop message is answered).
"""

from __future__ import annotations

from typing import Any

#: ``stop_reason`` of a status whose navigator has not stopped since its start.
NONE = 0
USER_STOPPED = 2


class StopWatch:
    """Feed it every status in order (:meth:`take`); it returns those that are stops."""

    def __init__(self) -> None:
        self._last: tuple[bool, int] | None = None
        self._stop_sent: float | None = None

    def stop_sent(self, stamp: float) -> None:
        """This program sent a stop at ``stamp`` (s, the module's clock).

        :param stamp: when the stop was sent (s, the module's clock); the first status stamped
            at or after it with reason 2 is that stop's answer.
        """
        self._stop_sent = stamp

    def take(self, statuses: list[Any]) -> list[Any]:
        """The stops among ``statuses`` (data views, oldest first).

        :param statuses: the navigator's statuses in order (NavigatorTransport data views).
        """
        stops = []
        for d in statuses:
            state = (bool(d.autonomous), int(d.stop_reason))
            stopped = not state[0] and state[1] != NONE
            changed = self._last is not None and self._last != state
            answered = (self._stop_sent is not None and state == (False, USER_STOPPED)
                        and d.timestamp.get_seconds() >= self._stop_sent)
            if stopped and (changed or answered):
                stops.append(d)
                if state[1] == USER_STOPPED:
                    self._stop_sent = None
            self._last = state
        return stops
