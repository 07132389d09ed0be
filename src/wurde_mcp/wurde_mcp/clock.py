"""The supervision clock: the time the MCP was actually watching, against which TTLs are judged.

A module is a zombie when it stays silent longer than its TTL (guide 5.2.1).  Measured on the
wall clock, that judgement also blames the module for time the MCP itself was not running — when
the kernel descheduled the MCP on a loaded machine, the heartbeats that arrived meanwhile sit
unread in its queue, and the first look after the gap sees every module "late".  That is where
false zombies under load came from.

So the MCP judges silence against its own loop lag.  This clock advances with the monotonic
clock while the supervision loop runs at its pace, but one gap between two looks counts at most
``max_gap_s``: the rest of a longer gap is the MCP's own stall (with the loop running every
20 ms, :data:`wurde_mcp.node.LOOP_S`, a gap past 50 ms means the MCP did not run), and is
*watched time* no module is charged for.  It also tells how long the MCP has been looking
steadily since its last stall.  The supervisor (:meth:`wurde_mcp.supervisor.Supervisor.tick`)
calls a module a zombie only when it is silent past its TTL by the monotonic clock, and either

- silent past its TTL in watched time too, or
- the MCP has been looking steadily for :data:`REVIEW_S` since its last stall — long enough to
  have taken in every beat that queued up while it was not running.

A hang is then caught at TTL + :data:`REVIEW_S` after the MCP's last stall at worst, and by the
plain TTL when the MCP runs smoothly; a stall of the MCP never turns into a zombie.
"""

from __future__ import annotations

import time

#: Longest gap between two looks that counts fully as watched time (s).
MAX_GAP_S = 0.05
#: Steady looking after a stall before wall-clock silence is trusted again (s).
REVIEW_S = 0.15


class SupervisionClock:
    """Watched time: monotonic time minus the MCP's own stalls."""

    def __init__(self, max_gap_s: float = MAX_GAP_S, *, start: float | None = None) -> None:
        """Start counting.

        :param max_gap_s: the longest gap between two looks that counts fully as watched time (s).
        :param start: the monotonic time of the first look (None: now).
        """
        self.max_gap_s = max_gap_s
        self._last = time.monotonic() if start is None else start
        self._watched = 0.0
        #: Seconds not counted (the MCP's own lag), gaps longer than ``max_gap_s``, longest gap.
        self.discounted_s = 0.0
        self.stalls = 0
        self.longest_gap_s = 0.0
        self._steady_since = self._last

    def tick(self, now: float | None = None) -> float:
        """Take a look at monotonic time ``now``; return the watched time.

        :param now: monotonic time (s); None: now.
        :returns: the watched time so far (s).
        """
        now = time.monotonic() if now is None else now
        gap = max(0.0, now - self._last)
        self._last = now
        counted = min(gap, self.max_gap_s)
        if gap > counted:
            self.stalls += 1
            self.discounted_s += gap - counted
            self._steady_since = now
        self.longest_gap_s = max(self.longest_gap_s, gap)
        self._watched += counted
        return self._watched

    def now(self) -> float:
        """Watched time at the last look."""
        return self._watched

    def steady_for(self, now: float) -> float:
        """Seconds the MCP has been looking without a stall, at monotonic time ``now``.

        :param now: monotonic time (s).
        """
        return now - self._steady_since
