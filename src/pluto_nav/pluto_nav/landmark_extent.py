"""How much of a landmark's line is wall: an interval whose ends are tied to neighbouring walls.

The filter estimates each wall's infinite line; where the wall begins and ends is bookkeeping
beside it.  Kept as plain positions ``t`` along the line, the ends would stay where the robot's
pose put them when they were seen: after a loop closure moves a corridor's cross wall by half a
metre, the corridor's walls would still end where the drifted estimate had them.  So each end is
stored *relative to a neighbour*: the nearest wall whose line crosses this one near the end (at
``min_angle`` or more, within ``radius``) is its *anchor*, and the end is kept as the offset from
the crossing of the two lines.  As the filter corrects the lines, the crossing moves and the end
with it (a corner stays a corner).  An end with no anchor nearby is kept as a point in the map,
projected onto the line as it is now: not as ``t``, which is measured from the foot of the
perpendicular from the map's origin, so that refining a short wall's angle by 0.01 rad would
slide an end 12 m from the origin by 12 cm.  An anchor that is forgotten or turns nearly
parallel leaves the end at the point it last gave.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from .line_landmark import along, intersection, point_at

__all__ = ['AnchorCandidates', 'End', 'Extent', 'choose_anchor', 'resolve']

#: An anchor whose line turns within this sine of parallel is given up (its crossing runs away).
_KEEP_SINE = math.sin(math.radians(10.0))


@dataclasses.dataclass
class End:
    """One end of an extent: ``t = crossing(anchor) + offset``, or the projection of ``point``.

    :ivar anchor: key of the anchoring landmark, or None.
    :ivar offset: m along the line from the crossing (anchored ends).
    :ivar point: ``(x, y)`` in the map (unanchored ends).
    :ivar t: the position it had when last resolved.
    """

    anchor: int | None
    offset: float
    point: tuple[float, float]
    t: float

    @classmethod
    def at(cls, line: NDArray, t: float) -> End:
        """An unanchored end at ``t`` on ``line``."""
        x, y = point_at(line[0], line[1], t)
        return cls(None, 0.0, (float(x), float(y)), t)

    def unanchor(self, line: NDArray) -> None:
        """Keep the end where it is now, as a point."""
        x, y = point_at(line[0], line[1], self.t)
        self.anchor, self.offset, self.point = None, 0.0, (float(x), float(y))


@dataclasses.dataclass(frozen=True)
class AnchorCandidates:
    """Landmarks that may anchor an end: keys ``(K,)``, lines ``(K, 2)``, intervals ``(K, 2)``."""

    keys: NDArray
    lines: NDArray
    intervals: NDArray

    @classmethod
    def empty(cls) -> AnchorCandidates:
        return cls(np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros((0, 2)))


def resolve(extents: Sequence[Extent], lines: NDArray, lines_of: Callable[[NDArray], NDArray]
            ) -> NDArray:
    """``(J, 2)``: the intervals ``[t_lo, t_hi]`` of ``extents`` on their current ``lines``
    ``(J, 2)``, all at once; ``lines_of(keys)`` gives the anchors' current lines ``(K, 2)`` (NaN
    for a forgotten landmark).  Updates each end's ``t``, and unanchors ends whose anchor is
    forgotten or has turned nearly parallel."""
    ends = [end for extent in extents for end in (extent.lo, extent.hi)]
    own = np.repeat(np.asarray(lines, dtype=np.float64).reshape(-1, 2), 2, axis=0)     # (2J, 2)
    t = np.empty(len(ends))
    tied = np.array([end.anchor is not None for end in ends], dtype=bool)
    if tied.any():
        index = np.flatnonzero(tied)
        other = lines_of(np.array([ends[i].anchor for i in index], dtype=np.int64))
        crossing, sine = intersection(own[index, 0], own[index, 1], other[:, 0], other[:, 1])
        t[index] = crossing + np.array([ends[i].offset for i in index])
        for i in index[~(np.abs(sine) >= _KEEP_SINE)]:            # NaN (forgotten) too
            ends[i].unanchor(own[i])
            tied[i] = False
    free = np.flatnonzero(~tied)
    if len(free):
        t[free] = along(own[free, 0], np.array([ends[i].point for i in free]).reshape(-1, 2))
    for end, value in zip(ends, t.tolist()):
        end.t = value
    out = t.reshape(-1, 2)
    for k in np.flatnonzero(out[:, 0] > out[:, 1]).tolist():   # corrections turned it inside out
        middle = float(out[k].mean())
        line = own[2 * k]
        extents[k].lo, extents[k].hi = End.at(line, middle), End.at(line, middle)
        out[k] = middle
    return out


def choose_anchor(line: NDArray, t: float, candidates: AnchorCandidates, *, exclude: int,
                  radius: float, min_angle: float) -> End:
    """The end at ``t`` on ``line`` anchored to the best candidate: the one whose line crosses
    at ``min_angle`` or more, at most ``radius`` from ``t``, with its own wall reaching within
    ``radius`` of the crossing (a wall nearby, not a far line that happens to pass), nearest by
    the sum of the two distances.  Unanchored when none qualifies."""
    if len(candidates.keys) == 0:
        return End.at(line, t)
    g, r = float(line[0]), float(line[1])
    crossing, sine = intersection(g, r, candidates.lines[:, 0], candidates.lines[:, 1])
    ok = (np.abs(sine) >= math.sin(min_angle)) & (candidates.keys != exclude)
    crossing = np.where(ok, crossing, 0.0)
    point = point_at(g, r, crossing)                                          # (K, 2)
    on_other = along(candidates.lines[:, 0], point)
    off_wall = np.maximum(0.0, np.maximum(candidates.intervals[:, 0] - on_other,
                                          on_other - candidates.intervals[:, 1]))
    shift = np.abs(crossing - t)
    ok &= (shift <= radius) & (off_wall <= radius)
    if not ok.any():
        return End.at(line, t)
    best = int(np.argmin(np.where(ok, shift + off_wall, np.inf)))
    return End(int(candidates.keys[best]), t - float(crossing[best]), (0.0, 0.0), t)


class Extent:
    """The seen part ``[lo, hi]`` of a landmark's line (see the module's description)."""

    def __init__(self, lo: End, hi: End) -> None:
        self.lo = lo
        self.hi = hi

    def __repr__(self) -> str:
        return f'Extent({self.lo}, {self.hi})'

    def interval(self, line: NDArray, lines_of: Callable[[NDArray], NDArray]
                 ) -> tuple[float, float]:
        """``(t_lo, t_hi)`` on the current ``line`` (see :func:`resolve`)."""
        lo, hi = resolve([self], np.asarray(line, dtype=np.float64).reshape(1, 2), lines_of)[0]
        return float(lo), float(hi)

    def flipped(self) -> Extent:
        """The same extent for the line in its other form (``t -> -t``)."""
        return Extent(End(self.hi.anchor, -self.hi.offset, self.hi.point, -self.hi.t),
                      End(self.lo.anchor, -self.lo.offset, self.lo.point, -self.lo.t))

    def drop_anchor(self, key: int, line: NDArray) -> None:
        """Unanchor the ends tied to landmark ``key`` (where they last were on ``line``)."""
        for end in (self.lo, self.hi):
            if end.anchor == key:
                end.unanchor(line)
