"""Data association for Pluto's poseModule (Pluto 7.1): which map wall each extracted line is.

For a predicted laser pose with covariance ``P``, every wall the laser could see
(:meth:`WallMap.visible`) is predicted in the laser frame with its Jacobian
(:func:`geometry.line_to_frame`).  An observed line is a *candidate* for a wall when its
innovation is inside the chi-square gate of 2 degrees of freedom at ``gate_probability`` and its
segment, put in the map at the predicted pose, lies within the extent of the wall's chain of
collinear walls (:attr:`WallMap.chain_extent`).  A line with no candidate gets a second chance
with the gate widened to ``fallback_gate_probability`` (its matches are flagged ``fallback``): an
odometry slip may put the prediction off by more than its covariance says, and the line that would
show it must not be the one thrown away; the filter accepts such matches only when they agree with
the others.

Each observed line goes to at most one wall.  Of several candidates, walls on one infinite line
count as one, a nearer parallel wall hides a farther one, and a line whose two best candidates are
within ``ambiguity_margin`` is not used at all: a wrong match does more harm than a missing one.
docs/pluto-nav.md ("Matching lines to walls") states every test with its settings.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import NamedTuple, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .geometry import lines_in_frame, wrap
from .lines import LineFeature
from .wall_map import WallMap

__all__ = ['Match', 'MatchArrays', 'MatchSettings', 'Matching', 'chi2_gate', 'match_lines']


def chi2_gate(probability: float) -> float:
    """The chi-square quantile of 2 degrees of freedom: ``-2 ln(1 - probability)``.

    :param probability: the probability mass inside the gate, in (0, 1).
    :raises ValueError: ``probability`` outside (0, 1).
    """
    if not 0.0 < probability < 1.0:
        raise ValueError(f'a gate probability must be in (0, 1), not {probability}')
    return -2.0 * math.log1p(-probability)


@dataclasses.dataclass(frozen=True)
class MatchSettings:
    """Tunables of :func:`match_lines` (defaults in brackets)."""

    #: Probability mass of the 2-dof chi-square gate [0.99: 9.21].
    gate_probability: float = 0.99
    #: The gate for lines that fit no wall within the first [0.99999: 23.0].
    fallback_gate_probability: float = 0.99999
    #: m: walls beyond this are not expected in a scan [81.82: a SICK LMS in cm mode].
    max_range: float = 81.82
    #: m: slack at the ends of a wall for the overlap test [0.2].
    overlap_tolerance: float = 0.2
    #: Fraction of an observed segment that must lie on the wall [0.5].
    min_coverage: float = 0.5
    #: rad: two lines this close in direction are parallel (for hiding) [0.1].
    parallel_angle: float = 0.1
    #: Squared-distance lead the best wall needs over a different second one [4.0].
    ambiguity_margin: float = 4.0

    def __post_init__(self) -> None:
        if chi2_gate(self.fallback_gate_probability) < chi2_gate(self.gate_probability):
            raise ValueError('fallback_gate_probability must not be below gate_probability')
        if not 0.0 <= self.min_coverage <= 1.0:
            raise ValueError(f'min_coverage must be in [0, 1], not {self.min_coverage}')


class MatchArrays(NamedTuple):
    """The matches of a :class:`Matching` as arrays, one row per match (what the filter uses).

    ``H = [[0, 0, -1], [hx, hy, 0]]``; ``r`` and ``s`` hold the ``(gamma-gamma, gamma-rho,
    rho-rho)`` entries of ``R`` and ``S``; ``v`` the innovations.
    """

    hx: NDArray
    hy: NDArray
    r: NDArray
    s: NDArray
    v: NDArray
    fallback: NDArray


class Match:
    """An observed line matched to a map wall (a view of one row of :class:`MatchArrays`).

    :ivar line: index into the observed lines.
    :ivar wall: index into the map's walls.
    :ivar distance: squared Mahalanobis distance ``v^T S^-1 v``.
    :ivar fallback: matched only within the widened fallback gate.
    """

    __slots__ = ('line', 'wall', 'distance', 'fallback', '_arrays', '_row')

    def __init__(self, line: int, wall: int, distance: float, fallback: bool,
                 arrays: MatchArrays, row: int) -> None:
        self.line, self.wall, self.distance, self.fallback = line, wall, distance, fallback
        self._arrays, self._row = arrays, row

    def __repr__(self) -> str:
        return (f'Match(line={self.line}, wall={self.wall}, distance={self.distance:.3g}, '
                f'fallback={self.fallback})')

    @property
    def innovation(self) -> NDArray:
        """``z - h(pose)``: ``(dgamma, drho)``, ``dgamma`` wrapped to ``(-pi, pi]``."""
        return self._arrays.v[self._row].copy()

    @property
    def innovation_covariance(self) -> NDArray:
        """``S = H P H^T + R``, 2x2."""
        return _symmetric(self._arrays.s[self._row])

    @property
    def measurement_covariance(self) -> NDArray:
        """``R``, the observed line's 2x2 covariance."""
        return _symmetric(self._arrays.r[self._row])

    @property
    def jacobian(self) -> NDArray:
        """``H = dh/d(x, y, theta)``, 2x3."""
        return np.array([[0.0, 0.0, -1.0],
                         [self._arrays.hx[self._row], self._arrays.hy[self._row], 0.0]])


def _symmetric(entries: NDArray) -> NDArray:
    a, b, d = entries.tolist()
    return np.array([[a, b], [b, d]])


_NO_ARRAYS = MatchArrays(np.zeros(0), np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)),
                         np.zeros((0, 2)), np.zeros(0, dtype=bool))


@dataclasses.dataclass(frozen=True)
class Matching:
    """What :func:`match_lines` made of the observed lines."""

    matches: list[Match]
    #: Lines left out because two different walls fitted them about equally well.
    ambiguous: list[int]
    #: Lines that fitted no wall.
    unmatched: list[int]
    #: ``matches`` as arrays.
    arrays: MatchArrays = _NO_ARRAYS


def match_lines(lines: Sequence[LineFeature], wall_map: WallMap, pose: ArrayLike,
                covariance: ArrayLike, settings: MatchSettings = MatchSettings()) -> Matching:
    """Match observed ``lines`` to ``wall_map`` for a laser at ``pose`` (see the module's description).

    :param lines: the scan's lines in the laser frame (:func:`.lines.extract_lines`).
    :param wall_map: the map's walls.
    :param pose: predicted laser pose ``(x, y, theta)`` in the map frame.
    :param covariance: its 3x3 covariance.
    :param settings: the gates, ranges and margins (:class:`MatchSettings`).
    """
    x, y, theta = np.asarray(pose, dtype=np.float64).reshape(3).tolist()
    p = np.asarray(covariance, dtype=np.float64).reshape(3, 3)
    if not lines:
        return Matching([], [], [])
    sigma_xy = math.sqrt(max(p[0, 0] + p[1, 1], 0.0))
    walls = wall_map.visible((x, y, theta), settings.max_range, margin=3.0 * sigma_xy)
    if len(walls) == 0:
        return Matching([], [], list(range(len(lines))))
    # Predicted lines h = (gamma', rho') and the rows of H = [[0, 0, -1], [hx, hy, 0]].
    h_gamma, h_rho, hx, hy = lines_in_frame(
        wall_map.gamma[walls], wall_map.rho[walls], (x, y, theta),
        cos_gamma=wall_map.cos_gamma[walls], sin_gamma=wall_map.sin_gamma[walls])
    # H P H^T, per wall.
    p_gg = p[2, 2]
    p_gr = -(hx * p[2, 0] + hy * p[2, 1])
    p_rr = hx * hx * p[0, 0] + 2.0 * hx * hy * p[0, 1] + hy * hy * p[1, 1]
    data = _line_table(lines)            # (L, 10): gamma, rho, R entries, ends, length
    v_gamma = cast(NDArray, wrap(data[:, 0:1] - h_gamma))                        # (L, W)
    v_rho = data[:, 1:2] - h_rho
    a = data[:, 2:3] + p_gg
    b = data[:, 3:4] + p_gr
    d = data[:, 4:5] + p_rr
    distance = (d * v_gamma * v_gamma - 2.0 * b * v_gamma * v_rho + a * v_rho * v_rho) / \
        (a * d - b * b)
    coverage, low, high = _coverage(data, wall_map, walls, (x, y, theta), sigma_xy,
                                    math.sqrt(max(p[2, 2], 0.0)), settings)
    overlaps = coverage >= settings.min_coverage
    candidate = (distance < chi2_gate(settings.gate_probability)) & overlaps
    wide = (distance < chi2_gate(settings.fallback_gate_probability)) & overlaps
    # A line with no candidate in the gate takes those of the fallback gate.
    counts = candidate.sum(axis=1)
    fallbacks = counts == 0
    options = np.where(fallbacks[:, None], wide, candidate)
    numbers = np.where(fallbacks, wide.sum(axis=1), counts).tolist()
    firsts = options.argmax(axis=1).tolist()
    chosen, ambiguous, unmatched = [], [], []
    for k, (number, best) in enumerate(zip(numbers, firsts)):
        if number == 0:
            unmatched.append(k)
            continue
        if number > 1:
            columns = options[k].nonzero()[0]
            strict = _strict_coverage(low[k, columns], high[k, columns],
                                      wall_map.chain_extent[walls[columns]], settings)
            best = _resolve(columns, distance[k, columns], strict, h_gamma[columns],
                            h_rho[columns], wall_map.line[walls[columns]], settings)
            if best is None:
                ambiguous.append(k)
                continue
        chosen.append((k, best))
    if not chosen:
        return Matching([], ambiguous, unmatched)
    ks, bs = np.array(chosen).T
    arrays = MatchArrays(hx[bs], hy[bs], data[ks, 2:5],
                         np.column_stack([a[ks, 0], b[ks, bs], d[ks, bs]]),
                         np.column_stack([v_gamma[ks, bs], v_rho[ks, bs]]), fallbacks[ks])
    wall_of, fallback_of, d2 = walls[bs].tolist(), arrays.fallback.tolist(), \
        distance[ks, bs].tolist()
    matches = [Match(k, wall_of[n], d2[n], fallback_of[n], arrays, n)
               for n, (k, _) in enumerate(chosen)]
    return Matching(matches, ambiguous, unmatched, arrays)


def _line_table(lines: Sequence[LineFeature]) -> NDArray:
    """``(L, 10)``: each line's ``gamma, rho``, its covariance's ``gg, gr, rr``, its ends'
    ``x1, y1, x2, y2`` and its length (one array from Python floats: cheaper than numpy's
    conversion of many small arrays)."""
    rows = []
    for line in lines:
        c = line.covariance.ravel().tolist()
        rows.append((line.gamma, line.rho, c[0], c[1], c[3], *line.start.tolist(),
                     *line.end.tolist(), line.length))
    return np.array(rows)


def _coverage(data: NDArray, wall_map: WallMap, walls: NDArray,
              pose: tuple[float, float, float], sigma_xy: float, sigma_theta: float,
              settings: MatchSettings) -> tuple[NDArray, NDArray, NDArray]:
    """``(coverage, low, high)``, each ``(L, W)``: the fraction of each observed segment that
    lies along each wall's chain, with the slack for the pose's uncertainty (0 where the segment
    is too long for the chain), and where the segment's ends fall along the wall."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    ends = data[:, 5:9].reshape(-1, 2, 2)                                          # (L, 2, 2)
    in_map = ends @ np.array([[c, s], [-s, c]]) + (x, y)
    along = in_map @ wall_map.along[:, walls]          # (L, 2, W): both ends' places on each wall
    low, high = along.min(axis=1), along.max(axis=1)
    reach = np.sqrt((ends * ends).sum(axis=2).max(axis=1))
    slack = (settings.overlap_tolerance + 3.0 * (sigma_xy + sigma_theta * reach))[:, None]
    first, last = wall_map.chain_extent[walls].T
    loose = np.minimum(high, last + slack) - np.maximum(low, first - slack)
    loose[data[:, 9:10] > wall_map.chain_length[walls] + 2.0 * settings.overlap_tolerance] = 0.0
    return np.maximum(loose, 0.0) / np.maximum(high - low, 1e-9), low, high


def _strict_coverage(low: NDArray, high: NDArray, extent: NDArray,
                     settings: MatchSettings) -> NDArray:
    """The coverage of one segment on some walls with only ``overlap_tolerance`` as slack."""
    overlap = np.minimum(high, extent[:, 1] + settings.overlap_tolerance) - \
        np.maximum(low, extent[:, 0] - settings.overlap_tolerance)
    return np.maximum(overlap, 0.0) / np.maximum(high - low, 1e-9)


def _resolve(columns: NDArray, distance: NDArray, strict: NDArray, h_gamma: NDArray,
             h_rho: NDArray, line_of: NDArray, settings: MatchSettings) -> int | None:
    """The one wall (of ``columns``, the candidates; the other arrays are theirs) an observed
    line with several candidates is, or None if ambiguous."""
    # 2. Hidden: a nearer parallel candidate on the same side that covers at all and as well.
    turn = np.abs(wrap(h_gamma[:, None] - h_gamma[None, :]))
    hides = (turn < settings.parallel_angle) & (h_rho[:, None] < h_rho[None, :]) & \
        (line_of[:, None] != line_of[None, :]) & (strict[:, None] >= strict[None, :]) & \
        (strict[:, None] > 0.0)                         # [i, j]: candidate i hides candidate j
    kept = (~hides.any(axis=0)).nonzero()[0].tolist()
    # 1. Same line: one representative per line, the best covered.
    by_line: dict[int, int] = {}
    for c in kept:
        line = int(line_of[c])
        if line not in by_line or strict[c] > strict[by_line[line]]:
            by_line[line] = c
    ranked = sorted(by_line.values(), key=lambda c: distance[c])
    # 3. Ambiguous: two different lines about equally close.
    if len(ranked) > 1 and distance[ranked[1]] - distance[ranked[0]] < settings.ambiguity_margin:
        return None
    return int(columns[ranked[0]])
