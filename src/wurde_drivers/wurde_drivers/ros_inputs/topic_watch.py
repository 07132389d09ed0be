"""Whether one of the robot's topics flows, and who speaks on it: said once when it falls silent,
once when it is back, once if it never came, and once if more than one node publishes on it
(wall clock, monotonic; the stamps are the robot's).

Several publishers on the robot's odometry or scan topic are worth a warning: ``ros_inputs`` takes
every message as the robot's, so another node's (a localization publishing its own ``odom``)
would be mixed into the robot's streams.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

__all__ = ['TopicWatch']

#: Seconds after start before a topic that never spoke is reported.
NEVER_AFTER_S = 5.0
#: Seconds between two looks at the topic's publishers (a graph query).
PUBLISHERS_EVERY_S = 2.0


class TopicWatch:
    """:meth:`heard` on every message, :meth:`check` every loop turn.

    :param what: names the topic in messages (``Odometry on /odom``).
    :param after: seconds without a message that make it silent.
    :param say: where the messages go (the module's logger).
    :param publishers: the nodes publishing on the topic now.
    """

    def __init__(self, what: str, after: float, say: Callable[[str], object],
                 publishers: Callable[[], list[str]]) -> None:
        self.what, self.after, self.say, self.publishers = what, after, say, publishers
        self.started = time.monotonic()
        self.last = -math.inf
        self.silent = False
        self.count = 0
        self._never_told = False
        self._crowd_told = False
        self._looked = -math.inf

    def heard(self) -> None:
        self.last = time.monotonic()
        self.count += 1
        if self.silent:
            self.silent = False
            self.say(f'{self.what} is back')

    def check(self) -> None:
        now = time.monotonic()
        if self.count and not self._crowd_told and now - self._looked >= PUBLISHERS_EVERY_S:
            self._looked = now
            nodes = self.publishers()
            if len(nodes) > 1:
                self._crowd_told = True
                self.say(f'{len(nodes)} nodes publish {self.what} ({", ".join(nodes)}): every '
                         'message is taken as the robot\'s; remap the others')
        if self.count == 0:
            if not self._never_told and now - self.started > max(NEVER_AFTER_S, self.after):
                self._never_told = True
                nodes = self.publishers()
                self.say(f'no {self.what} yet (publishers: {", ".join(nodes) or "none"}); '
                         'publishing nothing until it comes')
            return
        if not self.silent and now - self.last > self.after:
            self.silent = True
            self.say(f'{self.what} silent for {now - self.last:.1f} s; publishing nothing until it '
                     'is back')
