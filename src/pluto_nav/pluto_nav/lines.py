"""Line features from one laser scan: split-and-merge with total-least-squares fits.

Pluto's poseModule "extracts features from the laser scan then matches them to the map" (Pluto
7.1); the features are straight walls.  :func:`extract_lines` works on the scan's points in the
laser frame (x forward, y left): valid beams are cut into *runs* at invalid beams and gaps, a run
is *split* where a point lies more than ``split_distance`` off the chord between its ends
(iterative end-point fit), neighbouring pieces are *merged* again when their joint line fits, and
each piece of ``min_points`` points and ``min_length`` metres is *fitted*; docs/pluto-nav.md
("Line extraction") states each step's rule.

The covariance is the first-order propagation of independent range errors of standard deviation
``range_sigma`` through the total-least-squares fit (Pfister et al., "Weighted line fitting
algorithms for mobile robot map building", ICRA 2003; Arras & Siegwart 1997): a range error ``dr``
moves a point ``dr cos(phi - gamma) = dr rho / r`` along the line's normal, and a small change of
the line moves the normal offset at position ``t`` along the line by ``drho - t dgamma``, so with
``A = [-t_i, 1]`` and ``D = diag(sigma^2 rho^2 / r_i^2)``::

    cov(gamma, rho) = (A^T A)^-1  A^T D A  (A^T A)^-1

Every sum the fits need comes from prefix sums over the scan, so fitting a piece costs O(1) and
all pieces are fitted in one vectorised pass; only the splitting loop runs per piece.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    'DEFAULT_GAP_DISTANCE', 'DEFAULT_GAP_RATIO', 'DEFAULT_MIN_LENGTH', 'DEFAULT_MIN_POINTS',
    'DEFAULT_RANGE_SIGMA', 'DEFAULT_SPLIT_DISTANCE', 'SPLIT_SIGMAS', 'LineFeature', 'extract_lines',
    'scan_points',
]

#: m: standard deviation of one range reading (a SICK LMS in cm mode: about 1 cm).
DEFAULT_RANGE_SIGMA = 0.01
#: m: a point farther than this from its piece's chord splits the piece (or ``SPLIT_SIGMAS``
#: range standard deviations, if more: noise alone must not split a wall).
DEFAULT_SPLIT_DISTANCE = 0.05
SPLIT_SIGMAS = 5.0
#: m, and a multiple of the beam spacing ``r * dphi``: neighbours farther apart break the run
#: (5 spacings: a wall seen at up to about 78 degrees incidence stays one run).
DEFAULT_GAP_DISTANCE = 0.2
DEFAULT_GAP_RATIO = 5.0
#: A line needs at least this many points and this length (m).
DEFAULT_MIN_POINTS = 5
DEFAULT_MIN_LENGTH = 0.4
#: Neighbouring pieces whose fits differ by less than this (rad, m) are checked for a merge.
_MERGE_ANGLE = 0.2
_MERGE_SHIFT = 0.3


@dataclasses.dataclass(frozen=True, eq=False)
class LineFeature:
    """A straight wall seen in one scan, in the laser frame.

    :ivar gamma: rad, direction of the perpendicular from the laser to the line, in ``(-pi, pi]``.
    :ivar rho: m, distance from the laser to the line, ``>= 0``.
    :ivar covariance: 2x2 covariance of ``(gamma, rho)``.
    :ivar points: number of scan points fitted.
    :ivar first: beam index of the first point (robot order: beam 0 is on the right).
    :ivar last: beam index of the last point.
    :ivar start: ``(x, y)`` of the first point projected onto the line.
    :ivar end: ``(x, y)`` of the last point projected onto the line.
    :ivar length: m, from ``start`` to ``end``.
    """

    gamma: float
    rho: float
    covariance: NDArray
    points: int
    first: int
    last: int
    start: NDArray
    end: NDArray
    length: float


def scan_points(ranges: ArrayLike, *, angles: ArrayLike | None = None,
                start_angle: float = -math.pi / 2, angle_step: float | None = None,
                min_range: float = 0.0, max_range: float = math.inf
                ) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """The valid beams of a scan as points in the laser frame.

    :param ranges: ``(N,)`` metres in robot order.
    :param angles: ``(N,)`` beam directions; by default ``start_angle + i * angle_step`` with
        ``angle_step = pi / (N - 1)`` (N = 181 or 361: a SICK over 180 degrees).
    :param start_angle: rad, the first beam's direction when ``angles`` is None.
    :param angle_step: rad between beams when ``angles`` is None; None: ``pi / (N - 1)``.
    :param min_range: m; a range at or below it is no reading.
    :param max_range: m; a range at or beyond it is no reading.
    :returns: ``(index, r, x, y, dphi)`` of the valid beams (finite, ``min_range < r <
        max_range``); ``dphi`` is the absolute angle between each valid beam and the next.
    :raises ValueError: on a scan that is not 1-D, shorter than 2, or angles of another length.
    """
    r = np.asarray(ranges, dtype=np.float64)
    if r.ndim != 1 or len(r) < 2:
        raise ValueError(f'ranges must be a 1-D array of 2 or more values, not shape {r.shape}')
    if angles is None:
        step = math.pi / (len(r) - 1) if angle_step is None else float(angle_step)
        cos, sin = _beam_table(len(r), float(start_angle), step)
    else:
        phi = np.asarray(angles, dtype=np.float64)
        if phi.shape != r.shape:
            raise ValueError(f'{len(r)} ranges but angles of shape {phi.shape}')
        cos, sin = np.cos(phi), np.sin(phi)
    index = ((r > min_range) & (r < max_range)).nonzero()[0]     # NaN compares False
    rv = r[index]
    if angles is None:
        dphi = abs(step) * (index[1:] - index[:-1])
    else:
        dphi = np.abs(np.diff(phi[index]))
    return index, rv, rv * cos[index], rv * sin[index], dphi


@functools.lru_cache(maxsize=8)
def _beam_table(count: int, start: float, step: float) -> tuple[NDArray, NDArray]:
    """Cosines and sines of the beams of a regular scan (read-only; computed once per layout)."""
    phi = start + step * np.arange(count)
    cos, sin = np.cos(phi), np.sin(phi)
    cos.flags.writeable = sin.flags.writeable = False
    return cos, sin


def extract_lines(ranges: ArrayLike, *, angles: ArrayLike | None = None,
                  start_angle: float = -math.pi / 2, angle_step: float | None = None,
                  range_sigma: float = DEFAULT_RANGE_SIGMA, min_range: float = 0.0,
                  max_range: float = math.inf, split_distance: float | None = None,
                  gap_distance: float = DEFAULT_GAP_DISTANCE, gap_ratio: float = DEFAULT_GAP_RATIO,
                  min_points: int = DEFAULT_MIN_POINTS, min_length: float = DEFAULT_MIN_LENGTH
                  ) -> list[LineFeature]:
    """The straight walls in one scan, in beam order (see the module's description).

    :param ranges: ``(N,)`` metres in robot order; ``inf``, ``-1``, NaN, ``<= min_range`` and
        ``>= max_range`` are no reading.
    :param angles: beam directions, or ``start_angle`` and ``angle_step`` (see :func:`scan_points`).
    :param start_angle: rad, the first beam's direction when ``angles`` is None.
    :param angle_step: rad between beams when ``angles`` is None; None: ``pi / (N - 1)``.
    :param range_sigma: m, standard deviation of one range reading; sets the lines' covariances.
    :param min_range: m; see ``ranges``.
    :param max_range: m; see ``ranges``.
    :param split_distance: m; by default the larger of :data:`DEFAULT_SPLIT_DISTANCE` and
        :data:`SPLIT_SIGMAS` times ``range_sigma``.
    :param gap_distance: m; a run breaks where neighbouring points are farther apart than
        ``gap_distance + gap_ratio * r * dphi``.
    :param gap_ratio: beam spacings added to ``gap_distance`` (see there).
    :param min_points: the fewest points a line has (2 or more).
    :param min_length: m, the shortest line kept.
    :raises ValueError: on a malformed scan, a non-positive ``range_sigma`` or ``min_points < 2``.
    """
    if not range_sigma > 0.0:
        raise ValueError(f'range_sigma must be positive, not {range_sigma}')
    if min_points < 2:
        raise ValueError(f'min_points must be 2 or more, not {min_points}')
    if split_distance is None:
        split_distance = max(DEFAULT_SPLIT_DISTANCE, SPLIT_SIGMAS * range_sigma)
    index, r, x, y, dphi = scan_points(ranges, angles=angles, start_angle=start_angle,
                                       angle_step=angle_step, min_range=min_range,
                                       max_range=max_range)
    if len(index) < min_points:
        return []
    runs = _runs(index, r, x, y, dphi, gap_distance, gap_ratio)
    pieces = _split(runs, x, y, split_distance, min_points)
    if not pieces:
        return []
    run_starts = np.array([run[0] for run in runs])
    fit = _merge(pieces, run_starts, _PrefixSums(r, x, y), x, y, split_distance)
    return _features(fit, index, x, y, range_sigma, min_length)


def _runs(index: NDArray, r: NDArray, x: NDArray, y: NDArray, dphi: NDArray,
          gap_distance: float, gap_ratio: float) -> list[tuple[int, int]]:
    """Half-open ``[i, j)`` runs of valid points with no missing beam and no gap inside."""
    dx, dy = x[1:] - x[:-1], y[1:] - y[:-1]
    near = np.minimum(r[:-1], r[1:])
    limit = gap_distance + gap_ratio * near * dphi
    broken = (dx * dx + dy * dy > limit * limit) | (index[1:] - index[:-1] != 1)
    edges = [0, *(broken.nonzero()[0] + 1).tolist(), len(index)]
    return list(zip(edges[:-1], edges[1:]))


def _split(runs: list[tuple[int, int]], x: NDArray, y: NDArray, split_distance: float,
           min_points: int) -> list[tuple[int, int]]:
    """Iterative end-point fit: pieces ``[i, j)``, none with a point off its chord."""
    pieces: list[tuple[int, int]] = []
    stack = [run for run in reversed(runs) if run[1] - run[0] >= min_points]
    while stack:
        i, j = stack.pop()
        x0, y0 = float(x[i]), float(y[i])
        dx, dy = float(x[j - 1]) - x0, float(y[j - 1]) - y0
        norm = math.hypot(dx, dy)
        if norm == 0.0:
            continue
        # Signed distance (times norm) of every point from the chord.
        off = x[i:j] * dy - y[i:j] * dx
        off -= x0 * dy - y0 * dx
        high, low = int(off.argmax()), int(off.argmin())
        k = high if off[high] >= -off[low] else low
        if abs(float(off[k])) <= split_distance * norm:
            pieces.append((i, j))
            continue
        k += i
        if j - k - 1 >= min_points:
            stack.append((k + 1, j))
        if k - i >= min_points:
            stack.append((i, k))
    pieces.sort()
    return pieces


class _PrefixSums:
    """Prefix sums of ``1, x, y, x², xy, y²``, and the same weighted by ``1/r²``, over the
    points."""

    def __init__(self, r: NDArray, x: NDArray, y: NDArray) -> None:
        table = np.empty((12, len(x) + 1))
        table[:, 0] = 0.0
        terms = table[:, 1:]
        terms[0] = 1.0
        terms[1] = x
        terms[2] = y
        np.multiply(x, x, out=terms[3])
        np.multiply(x, y, out=terms[4])
        np.multiply(y, y, out=terms[5])
        np.multiply(terms[0:6], 1.0 / (r * r), out=terms[6:12])
        np.cumsum(terms, axis=1, out=terms)
        self.table = table

    def over(self, i: NDArray | int, j: NDArray | int) -> NDArray:
        """The 12 sums over the points ``[i, j)`` (``(12,)`` or ``(12, K)``)."""
        return self.table[:, j] - self.table[:, i]


def _tls(s: NDArray) -> tuple[NDArray, NDArray]:
    """Total-least-squares ``(gamma, rho)``, ``rho >= 0``, from the sums of :class:`_PrefixSums`."""
    n = s[0]
    mx, my = s[1] / n, s[2] / n
    sxx = s[3] - n * mx * mx
    sxy = s[4] - n * mx * my
    syy = s[5] - n * my * my
    gamma = 0.5 * np.arctan2(-2.0 * sxy, syy - sxx)
    rho = mx * np.cos(gamma) + my * np.sin(gamma)
    # rho < 0: the normal points away from the line; turn it round (gamma stays in (-pi, pi]).
    gamma = np.where(rho < 0.0, np.where(gamma > 0.0, gamma - math.pi, gamma + math.pi), gamma)
    return gamma, np.abs(rho)


def _fit(sums: _PrefixSums, pieces: list[tuple[int, int]]) -> tuple[NDArray, ...]:
    """``(i, j, sums, gamma, rho)`` of every piece ``[i, j)``, fitted at once."""
    i = np.array([p[0] for p in pieces])
    j = np.array([p[1] for p in pieces])
    s = sums.over(i, j)
    return (i, j, s, *_tls(s))


def _merge(pieces: list[tuple[int, int]], run_starts: NDArray, sums: _PrefixSums, x: NDArray,
           y: NDArray, split_distance: float) -> tuple[NDArray, ...]:
    """Join neighbouring pieces of one run (at most one dropped point apart) that make one
    straight line; :returns: the :func:`_fit` of the pieces after merging.

    Only pairs whose own fits are nearly the same line are checked point by point.
    """
    fit = _fit(sums, pieces)
    if len(pieces) < 2:
        return fit
    i, j, _, gamma, rho = fit
    turn = np.abs(np.mod(gamma[1:] - gamma[:-1] + math.pi, 2.0 * math.pi) - math.pi)
    same_run = np.searchsorted(run_starts, i[1:], 'right') == \
        np.searchsorted(run_starts, j[:-1] - 1, 'right')
    close = same_run & (i[1:] - j[:-1] <= 1) & (turn < _MERGE_ANGLE) & \
        (np.abs(rho[1:] - rho[:-1]) < _MERGE_SHIFT)
    if not close.any():
        return fit
    merged = [pieces[0]]
    for piece, candidate in zip(pieces[1:], close.tolist()):
        if candidate:
            a, b = merged[-1][0], piece[1]
            g, p = _tls(sums.over(a, b))
            c, s = math.cos(float(g)), math.sin(float(g))
            if float(np.abs(x[a:b] * c + y[a:b] * s - float(p)).max()) <= split_distance:
                merged[-1] = (a, b)
                continue
        merged.append(piece)
    return _fit(sums, merged) if len(merged) < len(pieces) else fit


def _features(fit: tuple[NDArray, ...], index: NDArray, x: NDArray, y: NDArray,
              range_sigma: float, min_length: float) -> list[LineFeature]:
    """Line features of the fitted pieces long enough; covariances from the sums."""
    i, j, s, gamma, rho = fit
    j = j - 1                                          # the last point, inclusive
    c, sn = np.cos(gamma), np.sin(gamma)
    # Endpoints: the first and last point of each piece projected onto its line.
    ends = np.empty((4, len(i)))
    off = x[i] * c + y[i] * sn - rho
    ends[0], ends[1] = x[i] - off * c, y[i] - off * sn
    off = x[j] * c + y[j] * sn - rho
    ends[2], ends[3] = x[j] - off * c, y[j] - off * sn
    length = np.hypot(ends[2] - ends[0], ends[3] - ends[1])
    # Position t along the line (direction (-sin, cos)): sums of t and t², plain and weighted
    # by 1/r².
    n, w = s[0], s[6]
    ss, cc, sc2 = sn * sn, c * c, 2.0 * sn * c
    st = c * s[2] - sn * s[1]
    stt = ss * s[3] - sc2 * s[4] + cc * s[5]
    swt = c * s[8] - sn * s[7]
    swtt = ss * s[9] - sc2 * s[10] + cc * s[11]
    det = n * stt - st * st
    # cov = M^-1 B M^-1 with M^-1 = [[a, b], [b, d]] and B = [[p, q], [q, u]].
    inv_det = 1.0 / np.where(det > 0.0, det, 1.0)
    a, b, d = n * inv_det, st * inv_det, stt * inv_det
    scale = (range_sigma * rho) ** 2
    p, q, u = swtt * scale, -swt * scale, w * scale
    ap_bq, aq_bu, bp_dq, bq_du = a * p + b * q, a * q + b * u, b * p + d * q, b * q + d * u
    cov = np.empty((len(i), 2, 2))
    cov[:, 0, 0] = ap_bq * a + aq_bu * b
    cov[:, 0, 1] = cov[:, 1, 0] = ap_bq * b + aq_bu * d
    cov[:, 1, 1] = bp_dq * b + bq_du * d
    keep = ((length >= min_length) & (det > 0.0)).tolist()
    first, last = index[i].tolist(), index[j].tolist()
    gl, rl, nl, ll = gamma.tolist(), rho.tolist(), n.tolist(), length.tolist()
    points = ends.T
    return [LineFeature(gamma=gl[k], rho=rl[k], covariance=cov[k], points=int(nl[k]),
                        first=first[k], last=last[k], start=points[k, 0:2], end=points[k, 2:4],
                        length=ll[k])
            for k in range(len(keep)) if keep[k]]
