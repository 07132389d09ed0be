"""When two SLAM landmarks are one wall.

A wall seen again after a long detour is first taken for a new wall (the robot's pose has drifted
further than the gate allows, or the old landmark was not in the local area); a wall seen in two
pieces becomes one when the gap between them is seen.  Two active landmarks ``i`` and ``j`` are
*the same wall* when all hold:

- their lines agree: the difference ``d = l_i - l_j`` (``l_j`` in the form closest to ``l_i``,
  :func:`.line_landmark.align`) has ``d^T D^-1 d`` inside the chi-square gate of 2 dof at
  ``probability``, with ``D`` the covariance of the difference from the joint covariance (so two
  landmarks mapped from nearly the same pose must agree to what the laser resolves, while a wall
  mapped before a long loop may be off by the loop's drift);
- their extents overlap or lie within ``gap`` of each other along the line;
- seen only from opposite sides, they also agree within ``other_side_tolerance`` in absolute
  terms (not the two faces of a thick wall);
- the pairing is unambiguous: no other landmark agrees with ``i`` about as well (within
  ``ambiguity_margin``) unless it predicts the same line as the best partner (then it is a third
  copy and merges next).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from .line_landmark import along, point_at

__all__ = ['MergeSettings', 'find_merges']

#: Lines closer than this (rad, m) are copies of each other (not an ambiguity).
_SAME_ANGLE = 0.05
_SAME_DISTANCE = 0.05


@dataclasses.dataclass(frozen=True)
class MergeSettings:
    """Tunables of :func:`find_merges` (defaults in brackets)."""

    #: Probability mass of the chi-square gate on the lines' difference, 2 dof [0.999].
    probability: float = 0.999
    #: m: extents this far apart still touch [0.3].
    gap: float = 0.3
    #: rad, m: absolute agreement needed when seen only from opposite sides [0.02, 0.03].
    other_side_tolerance: tuple[float, float] = (0.02, 0.03)
    #: Squared-distance lead the best partner needs over a different one [4.0].
    ambiguity_margin: float = 4.0


def find_merges(lines: NDArray, intervals: NDArray, covariance: NDArray, sides: NDArray,
                touched: Sequence[int], settings: MergeSettings
                ) -> list[tuple[int, int, float]]:
    """Pairs of the active landmarks to merge, best first, each landmark in at most one pair.

    :param lines: ``(J, 2)`` the active landmarks' lines; ``intervals`` ``(J, 2)`` their
        extents; ``covariance`` ``P_AA`` (pose first); ``sides`` their side bits.
    :param touched: positions of the landmarks changed by this scan (only pairs with one of
        them are checked: the others were checked before).
    :returns: ``(i, j, sign)``: positions, and -1 if ``j`` is ``i``'s line in the other form.
    """
    gate = -2.0 * math.log1p(-settings.probability)
    found: list[tuple[float, int, int, float]] = []
    for i in touched:
        pairs = _partners(i, lines, intervals, covariance, sides, gate, settings)
        if not pairs:
            continue
        pairs.sort()
        best_distance, j, sign = pairs[0]
        if any(other_distance - best_distance < settings.ambiguity_margin
               and not _same(lines[j], lines[k]) for other_distance, k, _ in pairs[1:]):
            continue
        found.append((best_distance, min(i, j), max(i, j), sign))
    found.sort()
    merges: list[tuple[int, int, float]] = []
    used: set[int] = set()
    for _, i, j, sign in found:
        if i in used or j in used:
            continue
        used.update((i, j))
        merges.append((i, j, sign))
    return merges


def _partners(i: int, lines: NDArray, intervals: NDArray, cov: NDArray, sides: NDArray,
              gate: float, settings: MergeSettings) -> list[tuple[float, int, float]]:
    """``(distance, j, sign)`` of every landmark that could be the same wall as ``i``."""
    g, r = lines[i]
    turn = np.mod(lines[:, 0] - g + math.pi, 2.0 * math.pi) - math.pi
    sign = np.where(np.abs(turn) > math.pi / 2, -1.0, 1.0)
    d_gamma = -(np.mod(turn + np.where(sign < 0, math.pi, 0.0) + math.pi, 2.0 * math.pi) - math.pi)
    d_rho = r - sign * lines[:, 1]
    near = (np.abs(d_gamma) < 0.3) & (np.abs(d_rho) < 1.0)
    near[i] = False
    j = np.flatnonzero(near)
    if len(j) == 0:
        return []
    # Covariance of the difference l_i - T l_j, T = diag(1, sign): P_ii + T P_jj T - 2 sym(P_ij T).
    a = 3 + 2 * i
    b = 3 + 2 * j
    rows = np.stack([b, b + 1], axis=1)                                           # (K, 2)
    p_jj = cov[rows[:, :, None], rows[:, None, :]]                                # (K, 2, 2)
    p_ij = cov[a:a + 2][:, rows].transpose(1, 0, 2)                               # (K, 2, 2)
    t = sign[j]
    p_jj[:, 0, 1] *= t
    p_jj[:, 1, 0] *= t
    p_ij[:, :, 1] *= t[:, None]
    diff = cov[a:a + 2, a:a + 2][None] + p_jj - p_ij - p_ij.transpose(0, 2, 1)
    da, db, dd = diff[:, 0, 0] + 1e-12, diff[:, 0, 1], diff[:, 1, 1] + 1e-12
    x, y = d_gamma[j], d_rho[j]
    distance = (dd * x * x - 2.0 * db * x * y + da * y * y) / (da * dd - db * db)
    ok = distance < gate
    # Seen only from opposite sides: the two faces of a thick wall are not one wall.
    angle_tol, rho_tol = settings.other_side_tolerance
    ok &= ((sides[i] & sides[j]) != 0) | ((np.abs(x) < angle_tol) & (np.abs(y) < rho_tol))
    # Extents overlapping, or within the gap, along i's line.
    ends = along(g, point_at(lines[j, 0:1], lines[j, 1:2], intervals[j]))         # (K, 2)
    ok &= np.maximum(intervals[i, 0], ends.min(axis=1)) - \
        np.minimum(intervals[i, 1], ends.max(axis=1)) <= settings.gap
    return [(float(distance[k]), int(j[k]), float(t[k])) for k in np.flatnonzero(ok)]


def _same(a: NDArray, b: NDArray) -> bool:
    """Whether two landmark lines are copies of each other (either form)."""
    turn = math.remainder(float(a[0] - b[0]), 2.0 * math.pi)
    if abs(turn) > math.pi / 2:
        return abs(math.remainder(turn + math.pi, 2.0 * math.pi)) < _SAME_ANGLE and \
            abs(a[1] + b[1]) < _SAME_DISTANCE
    return abs(turn) < _SAME_ANGLE and abs(a[1] - b[1]) < _SAME_DISTANCE
