"""The slamModule's correction: one EKF update with the matches of a scan that agree.

Each match says "line ``k`` of the scan is landmark ``key``"; its innovation and Jacobian come
from :func:`.line_landmark.observe` at the predicted state.  Before the update every match's
residual after the joint correction is tested against its expected spread (chi-square, 2 dof):
with ``C = H P H^T`` and ``S = C + R`` (all matches at once), the residuals are ``R S^-1 v`` and
their covariance ``R - C + C S^-1 C``, both in the measurements' space, so the test costs nothing
in the size of the map.  The worst offender is dropped and the test repeated until all agree (a
wrong match does not bend pose and map), as the poseModule's filter does.  Matches found only in
the association's widened fallback gate are used when they agree with the others, and on their
own only when ``min_fallback`` of them agree.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from .compressed_ekf import BLOCK, ROBOT, CompressedEKF
from .line_landmark import observe
from .lines import LineFeature

__all__ = ['Correction', 'correct']


@dataclasses.dataclass(frozen=True)
class Correction:
    """What :func:`correct` did: the matches ``(line, key)`` used, how many were dropped, and
    the normalised innovation squared per degree of freedom of those used (NaN if none)."""

    used: list[tuple[int, int]]
    rejected: int
    nis: float


def correct(ekf: CompressedEKF, lines: Sequence[LineFeature], matches: Sequence[tuple[int, int]],
            fallback: Sequence[bool], *, limit: float, min_fallback: int) -> Correction:
    """Update ``ekf`` with the ``matches`` that agree (see the module's description).

    :param limit: chi-square quantile (2 dof) a residual must stay within.
    """
    used, wide = list(matches), list(fallback)
    rejected = 0
    while used:
        h, cols, r, v = _stack(ekf, lines, used)
        c = h @ ekf.active_covariance[np.ix_(cols, cols)] @ h.T
        s_inv = np.linalg.inv(c + r)
        w = s_inv @ v
        misfit = _misfits(r @ w, r - c + c @ s_inv @ c)
        worst = int(np.argmax(misfit))
        if misfit[worst] > limit:
            used.pop(worst)
            wide.pop(worst)
            rejected += 1
            continue
        if all(wide) and len(used) < min_fallback:
            return Correction([], rejected + len(used), math.nan)
        ekf.update(cols, h, r, v)
        return Correction(used, rejected, float(v @ w) / (2 * len(used)))
    return Correction([], rejected, math.nan)


def _stack(ekf: CompressedEKF, lines: Sequence[LineFeature], used: Sequence[tuple[int, int]]
           ) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``(H, columns, R, v)`` of the matches, ``H`` over the pose and the landmarks involved."""
    keys = list(dict.fromkeys(key for _, key in used))
    starts = np.array([ekf.local_index(key) for key in keys])
    cols = np.concatenate([np.arange(ROBOT), (starts[:, None] + np.arange(BLOCK)).reshape(-1)])
    z, h_pose, h_line, _ = observe(ekf.means(keys), ekf.robot_mean)
    which = np.array([keys.index(key) for _, key in used])
    m = len(used)
    h = np.zeros((2 * m, len(cols)))
    h[:, :ROBOT] = h_pose[which].reshape(2 * m, ROBOT)
    for i, j in enumerate(which):
        h[2 * i:2 * i + 2, ROBOT + BLOCK * j:ROBOT + BLOCK * (j + 1)] = h_line[j]
    r = np.zeros((2 * m, 2 * m))
    for i, (k, _) in enumerate(used):
        r[2 * i:2 * i + 2, 2 * i:2 * i + 2] = lines[k].covariance
    observed = np.array([(lines[k].gamma, lines[k].rho) for k, _ in used])
    v = observed - z[which]
    v[:, 0] = np.mod(v[:, 0] + math.pi, 2.0 * math.pi) - math.pi
    return h, cols, r, v.reshape(-1)


def _misfits(residual: NDArray, spread: NDArray) -> NDArray:
    """Each match's ``e^T spread^-1 e`` from its 2x2 diagonal block (0 where degenerate)."""
    m = len(residual) // 2
    e = residual.reshape(m, 2)
    index = np.arange(m)
    blocks = spread.reshape(m, 2, m, 2)[index, :, index, :]                     # (m, 2, 2)
    a, b, d = blocks[:, 0, 0], blocks[:, 0, 1], blocks[:, 1, 1]
    det = a * d - b * b
    ok = det > 1e-18 * np.maximum(a * d, 1e-300)
    value = (d * e[:, 0] ** 2 - 2.0 * b * e[:, 0] * e[:, 1] + a * e[:, 1] ** 2) / \
        np.where(ok, det, 1.0)
    return np.where(ok, value, 0.0)
