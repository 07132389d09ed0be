"""The Kalman filter of Pluto's poseModule (Pluto 7.1): the laser pose in the map frame.

:meth:`PoseFilter.predict` composes the odometry increment between two scans (the
Laser_Dead-Reckoning stream's difference and its covariance, Pluto 3) onto the pose;
:meth:`PoseFilter.update` matches a scan's lines to the map (:func:`matching.match_lines`) and
corrects the pose with all matches at once.

The measurement model of a map line seen from the laser is linear in the pose (``gamma' = gamma -
theta``, ``rho' = ±(rho - x cos gamma - y sin gamma)``), so the update is one exact Gauss-Newton
step in information form on the 3x3 state, which keeps the covariance symmetric positive
definite by construction: ``P+ = (P^-1 + sum H^T R^-1 H)^-1``, ``x+ = x + P+ sum H^T R^-1 v``.

Robustness: after the correction every match's residual is tested against its expected spread
``R - H P+ H^T`` (chi-square, 2 dof, at ``consistency_probability``); the worst offender is
dropped and the correction redone until all agree (``rejected``), so a wrong match does not bend
the pose, while a prediction that was off (all lines agreeing on a large correction: an odometry
slip) is corrected rather than mistaken for outliers.  The covariance is kept symmetric with no
eigenvalue below :data:`COVARIANCE_FLOOR`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .geometry import compose, compose_jacobians, wrap
from .lines import LineFeature
from .matching import Match, Matching, MatchSettings, chi2_gate, match_lines
from .wall_map import WallMap

__all__ = ['COVARIANCE_FLOOR', 'FALLBACK_MIN_MATCHES', 'RECOVERY_INFLATION', 'RECOVERY_MIN_MATCHES',
           'REMATCH_STEP', 'PoseFilter', 'UpdateResult']

#: Smallest variance (m², rad²) the filter lets any direction of the covariance shrink to:
#: a floor against overconfidence and numerical collapse (1 mm, 0.06 degree).
COVARIANCE_FLOOR = 1e-6
#: Squared Mahalanobis length of a correction above which unmatched lines are matched again.
REMATCH_STEP = 1.0
#: Matches a correction needs when all of them come from the matcher's widened fallback gate.
FALLBACK_MIN_MATCHES = 2
#: When no line fits, the prediction's covariance is multiplied by this (standard deviations
#: doubled) for one more try, which needs this many lines to agree.
RECOVERY_INFLATION = 4.0
RECOVERY_MIN_MATCHES = 2


@dataclasses.dataclass(frozen=True)
class UpdateResult:
    """What one :meth:`PoseFilter.update` did.

    :ivar matches: number of lines used in the correction.
    :ivar nis: normalised innovation squared of the matches used, at the predicted pose,
        divided by its degrees of freedom (about 1 for a consistent filter); NaN without matches.
    :ivar accepted: whether the pose was corrected.
    :ivar rejected: matches found but not used: inconsistent with the others, or too few when
        they came from a widened gate only.
    :ivar ambiguous: lines left out as ambiguous by the matcher.
    :ivar lines: number of lines offered.
    :ivar used: the matches used.
    """

    matches: int
    nis: float
    accepted: bool
    rejected: int
    ambiguous: int
    lines: int
    used: tuple[Match, ...] = ()


class PoseFilter:
    """EKF on the laser pose ``(x, y, theta)`` in the map frame.

    :param settings: data association tunables (:class:`~.matching.MatchSettings`).
    :param consistency_probability: a match whose residual after the correction lies beyond
        the chi-square (2 dof) quantile at this probability is dropped [0.99999, the matcher's
        fallback gate: a line that alone fixes a direction is tested against the prediction,
        and then this test must let through what the fallback gate let in].
    """

    def __init__(self, *, settings: MatchSettings = MatchSettings(),
                 consistency_probability: float = 0.99999) -> None:
        """A filter at the origin with unit covariance; call :meth:`set_pose` first.

        :param settings: data association tunables (:class:`~.matching.MatchSettings`).
        :param consistency_probability: the chi-square (2 dof) quantile beyond which a match's residual
            after the correction drops it (see the class).
        """
        self._limit = chi2_gate(consistency_probability)
        self.settings = settings
        self._pose = np.zeros(3)
        self._cov = np.eye(3)

    @property
    def pose(self) -> NDArray:
        """The laser pose ``(x, y, theta)`` (a copy)."""
        return self._pose.copy()

    @property
    def covariance(self) -> NDArray:
        """Its 3x3 covariance (a copy)."""
        return self._cov.copy()

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """Start from ``pose`` with ``covariance``.

        :param pose: the laser pose ``(x, y, theta)`` in the map frame, metres and radians.
        :param covariance: 3x3 over (x, y, theta), symmetric positive definite.
        :raises ValueError: on a non-finite pose or a covariance that is not SPD.
        """
        p = np.asarray(pose, dtype=np.float64).reshape(3)
        c = np.asarray(covariance, dtype=np.float64).reshape(3, 3)
        if not np.isfinite(p).all():
            raise ValueError(f'pose must be finite, not {p}')
        _check_spd(c, 'covariance')
        self._pose = compose(p, (0.0, 0.0, 0.0))          # wraps theta
        self._cov = 0.5 * (c + c.T)

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        """Move by the odometry ``increment`` with its covariance.

        :param increment: ``(dx, dy, dtheta)`` in the previous laser frame (:func:`.geometry.relative`).
        :param increment_covariance: its 3x3 covariance, e.g.
            :func:`.odometry_model.increment_covariance`.
        :raises ValueError: on a non-finite increment or a covariance that is not symmetric
            positive semi-definite.
        """
        u = np.asarray(increment, dtype=np.float64).reshape(3)
        q = np.asarray(increment_covariance, dtype=np.float64).reshape(3, 3)
        if not np.isfinite(u).all():
            raise ValueError(f'increment must be finite, not {u}')
        _check_spd(q, 'increment_covariance', semi=True)
        j_pose, j_inc = compose_jacobians(self._pose, u)
        self._pose = compose(self._pose, u)
        cov = j_pose @ self._cov @ j_pose.T + j_inc @ q @ j_inc.T
        self._cov = 0.5 * (cov + cov.T)

    def update(self, lines: Sequence[LineFeature], wall_map: WallMap) -> UpdateResult:
        """Correct the pose with the lines of one scan (laser frame) matched to ``wall_map``.

        The prediction may be off by more than its covariance says (an odometry slip).  Matches
        found only in the matcher's widened fallback gate count if they agree with the others,
        and alone only if at least :data:`FALLBACK_MIN_MATCHES` of them agree.  If no line fits
        at all, the prediction itself is suspect: the lines are matched once more with its
        covariance times :data:`RECOVERY_INFLATION`, and that correction (from the inflated
        prediction) counts if at least :data:`RECOVERY_MIN_MATCHES` lines agree on it.  A
        correction that moves the pose by more than one standard deviation while some lines
        found no wall matches the lines again at the corrected pose and keeps whichever uses
        more lines.

        :param lines: the scan's lines in the laser frame (:func:`.lines.extract_lines`).
        :param wall_map: the a-priori map's walls.
        :returns: what the update did; the pose is unchanged when ``accepted`` is False.
        """
        prior_info = np.linalg.inv(self._cov)
        matching = match_lines(lines, wall_map, self._pose, self._cov, self.settings)
        best = self._solve(matching, self._pose, prior_info)
        if not matching.matches and len(lines) >= RECOVERY_MIN_MATCHES:
            wide = self._cov * RECOVERY_INFLATION
            again = match_lines(lines, wall_map, self._pose, wide, self.settings)
            if len(again.matches) >= RECOVERY_MIN_MATCHES:
                prior_info = np.linalg.inv(wide)
                found = self._solve(again, self._pose, prior_info)
                if found is not None and len(found.used) >= RECOVERY_MIN_MATCHES:
                    best, matching = found, again
        if best is not None and (matching.unmatched or matching.ambiguous):
            delta = _difference(best.pose, self._pose)
            if float(delta @ prior_info @ delta) > REMATCH_STEP:
                again = match_lines(lines, wall_map, best.pose, self._cov, self.settings)
                if len(again.matches) > len(best.used):
                    second = self._solve(again, best.pose, prior_info)
                    if second is not None and len(second.used) > len(best.used):
                        best, matching = second, again
        ambiguous = len(matching.ambiguous)
        if best is None:
            return UpdateResult(0, math.nan, False, len(matching.matches), ambiguous, len(lines))
        self._pose, self._cov = best.pose, best.covariance
        return UpdateResult(len(best.used), best.nis, True, best.rejected, ambiguous, len(lines),
                            best.used)

    def _solve(self, matching: Matching, at: NDArray, prior_info: NDArray) -> _Solution | None:
        """The correction from the matches (innovations taken at pose ``at``), dropping the
        match least consistent with the others while one fails the consistency test; None if
        no match is left (or the last one disagrees with the prediction).

        One Gauss-Newton step of the MAP problem, exact for the linear line model:
        ``x+ = at + P+ (sum H^T R^-1 v - P^-1 (at - x))`` with ``P+ = (P^-1 + sum H^T R^-1 H)^-1``,
        written out for ``H = [[0, 0, -1], [hx, hy, 0]]``.  A scan has a handful of matches, so
        this runs on Python floats: numpy's cost per call would dominate.
        """
        arrays = matching.arrays
        rows = [_Row(*values) for values in zip(
            arrays.hx.tolist(), arrays.hy.tolist(), *arrays.r.T.tolist(), *arrays.v.T.tolist(),
            arrays.fallback.tolist(), range(len(arrays.hx)))]
        ox, oy, ot = _difference(at, self._pose).tolist()
        prior = prior_info.tolist()
        prior_step = [prior[i][0] * ox + prior[i][1] * oy + prior[i][2] * ot for i in range(3)]
        rejected = 0
        while rows:
            info = [row[:] for row in prior]
            gain = [-prior_step[0], -prior_step[1], -prior_step[2]]
            for row in rows:
                row.add_to(info, gain, row.v0, row.v1)
            cov = _inverse_3x3(info)
            sx, sy, st = (cov[i][0] * gain[0] + cov[i][1] * gain[1] + cov[i][2] * gain[2]
                          for i in range(3))
            misfits = [row.misfit(sx, sy, st, cov) for row in rows]
            worst = max(range(len(rows)), key=misfits.__getitem__)
            if misfits[worst] > self._limit:
                if len(rows) == 1:
                    return None
                rows.pop(worst)
                rejected += 1
                continue
            if len(rows) < FALLBACK_MIN_MATCHES and all(row.fallback for row in rows):
                return None
            # NIS of the innovations at the prior pose (v + H offset), by Woodbury.
            scratch = [[0.0] * 3 for _ in range(3)]
            g0 = [0.0, 0.0, 0.0]
            plain = 0.0
            for row in rows:
                plain += row.add_to(scratch, g0, row.v0 - ot, row.v1 + row.hx * ox + row.hy * oy)
            nis = plain - sum(g0[i] * cov[i][j] * g0[j] for i in range(3) for j in range(3))
            pose = np.array([at[0] + sx, at[1] + sy, wrap(float(at[2]) + st)])
            used = tuple(matching.matches[row.index] for row in rows)
            return _Solution(pose, _floored(np.array(cov)), used, nis / (2 * len(rows)),
                             rejected)
        return None


class _Row:
    """One match for :meth:`PoseFilter._solve`: ``H = [[0, 0, -1], [hx, hy, 0]]``, ``R``,
    ``v``, as floats."""

    __slots__ = ('hx', 'hy', 'r00', 'r01', 'r11', 'v0', 'v1', 'fallback', 'index',
                 'ia', 'ib', 'id')

    def __init__(self, hx: float, hy: float, r00: float, r01: float, r11: float, v0: float,
                 v1: float, fallback: bool, index: int) -> None:
        self.hx, self.hy, self.r00, self.r01, self.r11 = hx, hy, r00, r01, r11
        self.v0, self.v1, self.fallback, self.index = v0, v1, fallback, index
        det = r00 * r11 - r01 * r01
        self.ia, self.ib, self.id = r11 / det, -r01 / det, r00 / det        # R^-1

    def add_to(self, info: list[list[float]], gain: list[float], v0: float, v1: float) -> float:
        """Add ``H^T R^-1 H`` to ``info`` and ``H^T R^-1 v`` to ``gain``.

        :returns: ``v^T R^-1 v``.
        """
        hx, hy, ia, ib, idd = self.hx, self.hy, self.ia, self.ib, self.id
        info[0][0] += idd * hx * hx
        info[1][1] += idd * hy * hy
        info[2][2] += ia
        info[0][1] += idd * hx * hy
        info[0][2] -= ib * hx
        info[1][2] -= ib * hy
        info[1][0], info[2][0], info[2][1] = info[0][1], info[0][2], info[1][2]
        gamma_part, rho_part = ia * v0 + ib * v1, ib * v0 + idd * v1
        gain[0] += hx * rho_part
        gain[1] += hy * rho_part
        gain[2] -= gamma_part
        return v0 * gamma_part + v1 * rho_part

    def misfit(self, sx: float, sy: float, st: float, cov: list[list[float]]) -> float:
        """Squared residual after the step ``(sx, sy, st)`` over its spread ``R - H P+ H^T``;
        0 where the spread vanishes (this match alone decided that direction)."""
        hx, hy = self.hx, self.hy
        e0 = self.v0 + st
        e1 = self.v1 - (hx * sx + hy * sy)
        s00 = self.r00 - cov[2][2]
        s01 = self.r01 + hx * cov[0][2] + hy * cov[1][2]
        s11 = self.r11 - (hx * hx * cov[0][0] + 2.0 * hx * hy * cov[0][1] + hy * hy * cov[1][1])
        det = s00 * s11 - s01 * s01
        if det <= 1e-12 * abs(s00 * s11):
            return 0.0
        return (s11 * e0 * e0 - 2.0 * s01 * e0 * e1 + s00 * e1 * e1) / det


def _inverse_3x3(m: list[list[float]]) -> list[list[float]]:
    """Inverse of a symmetric 3x3 matrix (by cofactors), symmetric."""
    (a, b, c), (_, d, e), (_, _, f) = m
    c00, c01, c02 = d * f - e * e, c * e - b * f, b * e - c * d
    c11, c12, c22 = a * f - c * c, b * c - a * e, a * d - b * b
    det = a * c00 + b * c01 + c * c02
    return [[c00 / det, c01 / det, c02 / det], [c01 / det, c11 / det, c12 / det],
            [c02 / det, c12 / det, c22 / det]]


@dataclasses.dataclass(frozen=True)
class _Solution:
    pose: NDArray
    covariance: NDArray
    used: tuple[Match, ...]
    nis: float
    rejected: int


def _difference(a: NDArray, b: NDArray) -> NDArray:
    """``a - b`` for poses, the angle wrapped."""
    return np.array([a[0] - b[0], a[1] - b[1], wrap(a[2] - b[2])])


def _check_spd(matrix: NDArray, name: str, *, semi: bool = False) -> None:
    """Raise ValueError unless the 3x3 ``matrix`` is finite, symmetric and positive definite
    (``semi``: semi-definite, allowing round-off), by its principal minors."""
    (a, b, c), (b2, d, e), (c2, e2, f) = matrix.tolist()
    scale = max(abs(a), abs(d), abs(f), 1e-300)
    if not all(math.isfinite(v) for v in (a, b, c, d, e, f, b2, c2, e2)) or \
            max(abs(b - b2), abs(c - c2), abs(e - e2)) > 1e-9 * scale:
        raise ValueError(f'{name} must be finite and symmetric, not {matrix.tolist()}')
    minors = (a, d, f, a * d - b * b, a * f - c * c, d * f - e * e,
              a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d))
    if semi:
        tolerance = (-1e-12 * scale, -1e-12 * scale ** 2, -1e-12 * scale ** 3)
        ok = all(m >= tolerance[0] for m in minors[0:3]) and \
            all(m >= tolerance[1] for m in minors[3:6]) and minors[6] >= tolerance[2]
    else:
        ok = minors[0] > 0.0 and minors[3] > 0.0 and minors[6] > 0.0
    if not ok:
        raise ValueError(f'{name} must be positive {"semi-" if semi else ""}definite, not '
                         f'{matrix.tolist()}')


def _floored(cov: NDArray) -> NDArray:
    """``cov`` (SPD) with no eigenvalue below :data:`COVARIANCE_FLOOR`: if the smallest is
    short of it, the shortfall is added to the diagonal (every direction gains at most that).

    The smallest eigenvalue of an SPD 3x3 matrix is at least ``det`` over the sum of its
    principal 2x2 minors (``1 / sum(1 / eigenvalue)``), which settles the common case without
    an eigendecomposition.
    """
    (a, b, c), (_, d, e), (_, _, f) = cov.tolist()
    det = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d)
    minors = (a * d - b * b) + (a * f - c * c) + (d * f - e * e)
    if det >= COVARIANCE_FLOOR * minors:
        return cov
    shortfall = COVARIANCE_FLOOR - float(np.linalg.eigvalsh(cov)[0])
    return cov + np.eye(3) * shortfall if shortfall > 0.0 else cov
