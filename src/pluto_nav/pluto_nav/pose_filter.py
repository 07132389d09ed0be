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
from .matching import Match, MatchSettings, chi2_gate, match_lines
from .wall_map import WallMap

__all__ = ['COVARIANCE_FLOOR', 'FALLBACK_MIN_MATCHES', 'REMATCH_STEP', 'PoseFilter', 'UpdateResult']

#: Smallest variance (m², rad²) the filter lets any direction of the covariance shrink to:
#: a floor against overconfidence and numerical collapse (1 mm, 0.06 degree).
COVARIANCE_FLOOR = 1e-6
#: Squared Mahalanobis length of a correction above which unmatched lines are matched again.
REMATCH_STEP = 1.0
#: Matches a correction needs when all of them come from the matcher's widened fallback gate.
FALLBACK_MIN_MATCHES = 2


@dataclasses.dataclass(frozen=True)
class UpdateResult:
    """What one :meth:`PoseFilter.update` did.

    :ivar matches: number of lines used in the correction.
    :ivar nis: normalised innovation squared of the matches used, at the predicted pose,
        divided by its degrees of freedom (about 1 for a consistent filter); NaN without matches.
    :ivar accepted: whether the pose was corrected.
    :ivar rejected: matches dropped as inconsistent with the others.
    :ivar ambiguous: lines left out as ambiguous by the matcher.
    :ivar lines: number of lines offered.
    :ivar used: the matches used, nearest first.
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
        """Start from ``pose`` with ``covariance`` (3x3, symmetric positive definite).

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
        """Move by the odometry ``increment`` (in the previous laser frame) with its covariance.

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
        and alone only if at least :data:`FALLBACK_MIN_MATCHES` of them agree.  A correction
        that moves the pose by more than one standard deviation while some lines found no wall
        matches the lines again at the corrected pose and keeps whichever uses more lines.
        """
        prior_info = _inverse_spd(self._cov)
        matching = match_lines(lines, wall_map, self._pose, self._cov, self.settings)
        best = self._solve(matching.matches, self._pose, prior_info)
        if best is not None and (matching.unmatched or matching.ambiguous):
            delta = _difference(best.pose, self._pose)
            if float(delta @ prior_info @ delta) > REMATCH_STEP:
                again = match_lines(lines, wall_map, best.pose, self._cov, self.settings)
                if len(again.matches) > len(best.used):
                    second = self._solve(again.matches, best.pose, prior_info)
                    if second is not None and len(second.used) > len(best.used):
                        best, matching = second, again
        ambiguous = len(matching.ambiguous)
        if best is None:
            return UpdateResult(0, math.nan, False, len(matching.matches), ambiguous, len(lines))
        self._pose, self._cov = best.pose, best.covariance
        return UpdateResult(len(best.used), best.nis, True, best.rejected, ambiguous, len(lines),
                            best.used)

    def _solve(self, matches: Sequence[Match], at: NDArray,
               prior_info: NDArray) -> _Solution | None:
        """The correction from ``matches`` (innovations taken at pose ``at``), dropping the
        match least consistent with the others while one is beyond the joint test; None if no
        match is left (or the last one disagrees with the prediction).

        One Gauss-Newton step of the MAP problem, exact for the linear line model:
        ``x+ = at + P+ (sum H^T R^-1 v - P^-1 (at - x))`` with ``P+ = (P^-1 + sum H^T R^-1 H)^-1``.
        """
        used = list(matches)
        limit = self._limit
        offset = _difference(at, self._pose)
        rejected = 0
        while used:
            h = np.array([m.jacobian for m in used])                           # (m, 2, 3)
            r = np.array([m.measurement_covariance for m in used])             # (m, 2, 2)
            v = np.array([m.innovation for m in used])                         # (m, 2)
            r_inv = _inverse_2x2(r)
            ht_rinv = h.transpose(0, 2, 1) @ r_inv                              # (m, 3, 2)
            info = prior_info + (ht_rinv @ h).sum(axis=0)
            cov = _inverse_spd(info)
            step = cov @ ((ht_rinv @ v[:, :, None]).sum(axis=0)[:, 0] - prior_info @ offset)
            # Each match's residual after the correction, against its own expected spread.
            residual = v - h @ step
            spread = r - h @ cov @ h.transpose(0, 2, 1)
            a, b, d = spread[:, 0, 0], spread[:, 0, 1], spread[:, 1, 1]
            det = a * d - b * b
            e0, e1 = residual[:, 0], residual[:, 1]
            misfit = np.where(det > 1e-18 * np.maximum(a * d, 1e-300),
                              (d * e0 * e0 - 2.0 * b * e0 * e1 + a * e1 * e1) /
                              np.where(det > 0.0, det, 1.0), 0.0)
            worst = int(np.argmax(misfit))
            if misfit[worst] > limit:
                if len(used) == 1:
                    return None
                used.pop(worst)
                rejected += 1
                continue
            # NIS of the innovations at the prior pose (v + H offset), by Woodbury.
            v0 = v + h @ offset
            g0 = (ht_rinv @ v0[:, :, None]).sum(axis=0)[:, 0]
            nis = float(np.einsum('mi,mij,mj->', v0, r_inv, v0) - g0 @ cov @ g0)
            if len(used) < FALLBACK_MIN_MATCHES and all(m.fallback for m in used):
                return None
            pose = np.array([at[0] + step[0], at[1] + step[1], wrap(at[2] + step[2])])
            return _Solution(pose, _floored(cov), tuple(used), nis / (2 * len(used)), rejected)
        return None


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


def _inverse_2x2(m: NDArray) -> NDArray:
    """Inverses of ``(k, 2, 2)`` symmetric positive definite matrices, in closed form."""
    a, b, d = m[:, 0, 0], m[:, 0, 1], m[:, 1, 1]
    det = a * d - b * b
    out = np.empty_like(m)
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = d / det, -b / det, -b / det, a / det
    return out


def _inverse_spd(m: NDArray) -> NDArray:
    inv = np.linalg.inv(m)
    return 0.5 * (inv + inv.T)


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
    """``cov`` (SPD) with no eigenvalue below :data:`COVARIANCE_FLOOR`.

    The smallest eigenvalue of an SPD 3x3 matrix is at least ``4 det / trace²``, which settles
    the common case without an eigendecomposition.
    """
    (a, b, c), (_, d, e), (_, _, f) = cov.tolist()
    det = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d)
    trace = a + d + f
    if 4.0 * det >= COVARIANCE_FLOOR * trace * trace:
        return cov
    values, vectors = np.linalg.eigh(cov)
    if values[0] >= COVARIANCE_FLOOR:
        return cov
    values = np.maximum(values, COVARIANCE_FLOOR)
    floored = (vectors * values) @ vectors.T
    return 0.5 * (floored + floored.T)
