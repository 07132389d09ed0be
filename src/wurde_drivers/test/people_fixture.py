"""Helpers for the tests of the simulator's people: configs with ``<person>`` lines, the truth topic.

A config is config/sim copied by :func:`sim_fixture.sim_config` (office map, the robot at the
``start`` place (3, 7.5) facing east, radius 0.35 m; the laser 0.2 m ahead, 0.5 m up), with the
given ``<person .../>`` elements one a line before its end, so each person's line is known.
"""

from __future__ import annotations

import bisect
import pathlib
import re
from collections.abc import Sequence
from typing import Any

from sim_fixture import sim_config

#: config/sim's start and robot radius.
START = (3.0, 7.5, 0.0)
ROBOT_RADIUS = 0.35
BASE = 'PlutoBase'
PEOPLE_TOPIC = f'/{BASE}/ground_truth/people'


def people_config(directory: pathlib.Path, people: Sequence[str],
                  **edits: Any) -> tuple[pathlib.Path, dict[str, int]]:
    """config/sim (with :func:`sim_config`'s ``edits``) plus ``people``, each a whole
    ``<person .../>`` element on one line; returns the file and each person's line by name
    (the line of the last of two that share a name)."""
    path = sim_config(directory, **edits)
    text = path.read_text()
    closing = text.rindex('</sim-config>')
    path.write_text(text[:closing] + ''.join(f'  {person}\n' for person in people) + text[closing:])
    lines = {}
    for number, line in enumerate(path.read_text().splitlines(), 1):
        found = re.search(r'<person\b[^>]*\bname="([^"]*)"', line)
        if found:
            lines[found.group(1)] = number
    return path, lines


class Truth:
    """The people's truth as received: stamps and, per person name, ``(x, y)`` at each."""

    def __init__(self) -> None:
        self.stamps: list[float] = []
        self.positions: dict[str, list[tuple[float, float]]] = {}
        self.markers: list[Any] = []

    def add(self, message: Any) -> None:
        """One MarkerArray (every person, one stamp)."""
        stamp = message.markers[0].header.stamp
        self.stamps.append(stamp.sec + stamp.nanosec * 1e-9)
        for marker in message.markers:
            self.positions.setdefault(marker.text, []).append((marker.pose.position.x,
                                                               marker.pose.position.y))
            self.markers.append(marker)

    def bracket(self, name: str, stamp: float) -> tuple[tuple[float, float], tuple[float, float], float] | None:
        """The positions of ``name`` at the truth stamps just before and after ``stamp`` and the
        fraction of the way; None when ``stamp`` is not between two received stamps."""
        after = bisect.bisect_right(self.stamps, stamp)
        if after == 0 or after == len(self.stamps):
            return None
        before = after - 1
        span = self.stamps[after] - self.stamps[before]
        if span > 0.25:                      # a gap (a message lost to a slow start): no bracket
            return None
        positions = self.positions[name]
        return positions[before], positions[after], (stamp - self.stamps[before]) / span

    def at(self, name: str, stamp: float) -> tuple[float, float] | None:
        """Where ``name`` was at ``stamp``, interpolated between the truth stamps around it."""
        found = self.bracket(name, stamp)
        if found is None:
            return None
        (x0, y0), (x1, y1), f = found
        return x0 + f * (x1 - x0), y0 + f * (y1 - y0)
