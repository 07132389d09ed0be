"""A person's walk: where a moving obstacle of the simulator is, as a pure function of the stamp.

The dummies are separate processes, each with a clock of its own (:class:`~.clock.SimClock`,
anchored at the wall clock when the process started), and they never tell each other where the
people are.  So a person's position is a pure, deterministic function of the absolute stamp
(seconds since the Unix epoch, the stamps every dummy puts on its data) and of the config: the
base, which moves the robot among the people, and the laser, which scans them at a scan's centre
stamp, compute the same positions for the same stamp without talking to each other.  A base the
MCP restarts finds everyone where they would have been, since nothing about the people lives in a
process.

A walk is a list of waypoints walked in straight legs at ``speed`` (m/s), standing ``pause``
seconds at each waypoint before leaving it:

- ``loop``: ``p0 → p1 → … → pn-1 → p0`` and round again;
- ``back-and-forth``: ``p0 → … → pn-1 → … → p0`` (the way back is the way there, reversed).

One cycle lasts the pauses plus the legs' lengths over the speed; the walk repeats for ever, and
the pose at stamp ``t`` is that at ``t mod cycle`` of the cycle, which starts at stamp 0 with the
pause at ``p0``.  So the phase of the people at the robot's start depends on the wall-clock time
a run starts: two runs of one config meet the people at different places (a run without people
repeats exactly, as before).  The heading is the direction of the leg being walked, and while
pausing at a waypoint that of the leg leaving it (a box turns on the spot as it arrives).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['BACK_AND_FORTH', 'LOOP', 'MAX_SPEED', 'MODES', 'Walk']

LOOP = 'loop'
BACK_AND_FORTH = 'back-and-forth'
MODES = (LOOP, BACK_AND_FORTH)
#: m/s: the fastest a simulated person walks (a brisk walk; a robot must cope with it).
MAX_SPEED = 1.5
#: m: two waypoints closer than this are the same place (a leg of no length).
MIN_LEG = 1e-3


def _route(points: Sequence[tuple[float, float]], mode: str) -> list[tuple[float, float]]:
    """The waypoints in the order walked in one cycle, the first repeated at the end."""
    if mode == LOOP:
        return [*points, points[0]]
    return [*points, *points[-2::-1]]


@dataclasses.dataclass(frozen=True)
class Walk:
    """Waypoints walked at ``speed`` with ``pause`` seconds at each, repeated for ever.

    :param points: two or more ``(x, y)`` waypoints in metres, map frame.
    :param speed: m/s, in ``(0, MAX_SPEED]``.
    :param pause: seconds standing at each waypoint (``>= 0``).
    :param mode: :data:`LOOP` or :data:`BACK_AND_FORTH`.
    :raises ValueError: on fewer than two points, a non-finite value, a speed out of range, a
        negative pause, an unknown mode, or a leg of no length (two consecutive waypoints the
        same, closer than :data:`MIN_LEG`, or a loop whose last point repeats its first).
    """

    points: tuple[tuple[float, float], ...]
    speed: float
    pause: float = 0.0
    mode: str = LOOP
    _start: NDArray = dataclasses.field(init=False, repr=False, compare=False)
    _edge: NDArray = dataclasses.field(init=False, repr=False, compare=False)
    _length: NDArray = dataclasses.field(init=False, repr=False, compare=False)
    _heading: NDArray = dataclasses.field(init=False, repr=False, compare=False)
    _begin: NDArray = dataclasses.field(init=False, repr=False, compare=False)
    _cycle: float = dataclasses.field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        points = tuple((float(x), float(y)) for x, y in self.points)
        object.__setattr__(self, 'points', points)
        if len(points) < 2:
            raise ValueError(f'a walk needs at least 2 points, got {len(points)}')
        if not all(math.isfinite(v) for point in points for v in point):
            raise ValueError('the points of a walk must be finite')
        if not (math.isfinite(self.speed) and 0.0 < self.speed <= MAX_SPEED):
            raise ValueError(f'speed {self.speed} m/s is not in (0, {MAX_SPEED}]')
        if not (math.isfinite(self.pause) and self.pause >= 0.0):
            raise ValueError(f'pause {self.pause} s must be 0 or more')
        if self.mode not in MODES:
            raise ValueError(f'mode {self.mode!r} is not one of {", ".join(MODES)}')
        route = np.array(_route(points, self.mode))
        start, edge = route[:-1], np.diff(route, axis=0)
        length = np.hypot(edge[:, 0], edge[:, 1])
        if np.any(length < MIN_LEG):
            leg = int(np.argmin(length))
            if self.mode == LOOP and leg == len(points) - 1:
                raise ValueError('the last point repeats the first: a loop closes by itself, '
                                 'leave the repeated point out')
            raise ValueError(f'points {leg + 1} and {leg + 2} are the same place')
        walking = length / self.speed
        begin = np.concatenate([[0.0], np.cumsum(self.pause + walking)])
        for name, value in (('_start', start), ('_edge', edge), ('_length', length),
                            ('_heading', np.arctan2(edge[:, 1], edge[:, 0])), ('_begin', begin[:-1])):
            value.flags.writeable = False
            object.__setattr__(self, name, value)
        object.__setattr__(self, '_cycle', float(begin[-1]))

    @property
    def cycle(self) -> float:
        """Seconds of one round: every pause and every leg once."""
        return self._cycle

    @property
    def legs(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """The straight legs of one cycle, in the order walked: ``((x1, y1), (x2, y2))``."""
        return [(tuple(map(float, a)), tuple(map(float, a + e)))  # type: ignore[misc]
                for a, e in zip(self._start, self._edge)]

    def poses_at(self, stamps: ArrayLike) -> NDArray:
        """``(N, 3)``: ``x, y, heading`` at each of ``stamps`` (seconds, any origin but the
        epoch's for agreement between processes)."""
        t = np.asarray(stamps, dtype=np.float64).reshape(-1)
        if not np.all(np.isfinite(t)):
            raise ValueError('stamps must be finite')
        into_cycle = np.mod(t, self._cycle)
        leg = np.clip(np.searchsorted(self._begin, into_cycle, side='right') - 1, 0, len(self._begin) - 1)
        walked = (into_cycle - self._begin[leg] - self.pause) * self.speed      # < 0 while pausing
        fraction = np.clip(walked / self._length[leg], 0.0, 1.0)
        xy = self._start[leg] + fraction[:, None] * self._edge[leg]
        return np.column_stack([xy, self._heading[leg]])

    def pose_at(self, stamp: float) -> tuple[float, float, float]:
        """``(x, y, heading)`` at ``stamp``."""
        x, y, heading = self.poses_at([stamp])[0]
        return float(x), float(y), float(heading)
