"""Data association for the slamModule: which landmark each line of a scan is.

For every observed line (laser frame) and active landmark the filter predicts the landmark in the
laser frame (:func:`.line_landmark.observe`) with the innovation covariance
``S = H P H^T + R`` over the laser pose *and* the landmark (their correlation included: a
landmark mapped from here is known well relative to the robot however lost the map is).  A
landmark is a *candidate* for a line when it passes the chi-square gate (``gate_probability``),
the laser is not edge-on to its line (``min_facing``), the segment reaches its extent
(``overlap_tolerance``) and, for a landmark seen so far only from the other side, the fit is
within ``other_side_tolerance`` (the two faces of a thick wall must not be taken for each other);
docs/pluto-nav.md ("SLAM data association") states each test.

A line with no candidate gets a second chance with the gate widened to
``fallback_gate_probability`` (its match is flagged): odometry can be off by more than its
covariance says, and the lines that would show it must not all be taken for new walls.  The
filter uses fallback matches only when they agree with the others, and alone only when two or
more agree.  Of several candidates the nearest in Mahalanobis distance wins unless a different
one is within ``ambiguity_margin`` of it (a wall and its duplicate about to merge are not
different; a parallel candidate behind the best one is hidden by it).  An ambiguous line is used
neither to correct nor to start a landmark.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from .geometry import transform_points
from .line_landmark import along, observe
from .lines import LineFeature

__all__ = ['Association', 'AssociationSettings', 'SIDE_NEGATIVE', 'SIDE_POSITIVE', 'associate',
           'side_of']

#: Bits of a landmark's ``sides``: seen with the laser on the positive or negative side of its
#: line (the sign of :func:`.line_landmark.observe`'s offset).
SIDE_POSITIVE = 1
SIDE_NEGATIVE = 2

#: Candidates predicting lines closer than this (rad, m) are one wall (a duplicate).
_SAME_ANGLE = 0.05
_SAME_DISTANCE = 0.05
#: rad: candidates this close in direction are parallel (one may hide the other).
_PARALLEL = 0.1


def side_of(offset: float | NDArray) -> int | NDArray:
    """The side bit of a landmark's signed offset from the laser."""
    return np.where(np.asarray(offset) < 0.0, SIDE_NEGATIVE, SIDE_POSITIVE)


@dataclasses.dataclass(frozen=True)
class AssociationSettings:
    """Tunables of :func:`associate` (defaults in brackets)."""

    #: Probability mass of the chi-square gate, 2 dof [0.999: 13.8].
    gate_probability: float = 0.999
    #: The gate for lines that fit no landmark within the first [0.99999: 23.0].
    fallback_gate_probability: float = 0.99999
    #: m: slack at the ends of a landmark's extent [0.2].
    overlap_tolerance: float = 0.2
    #: m: a laser closer than this to a line sees it edge-on [0.05].
    min_facing: float = 0.05
    #: rad, m: innovation allowed for a landmark seen only from the other side [0.05, 0.05].
    other_side_tolerance: tuple[float, float] = (0.05, 0.05)
    #: Squared-distance lead the best candidate needs over a different one [4.0].
    ambiguity_margin: float = 4.0


@dataclasses.dataclass(frozen=True)
class Association:
    """Lines of a scan against the active landmarks.

    :ivar matches: ``(line, landmark position in the active list)`` pairs.
    :ivar fallback: for each match, whether it was found only in the widened gate.
    :ivar ambiguous: lines fitting two different landmarks about equally well.
    :ivar unmatched: lines with no candidate.
    :ivar offsets: ``(J,)`` signed offset of each active landmark's line from the laser.
    """

    matches: list[tuple[int, int]]
    fallback: list[bool]
    ambiguous: list[int]
    unmatched: list[int]
    offsets: NDArray


def associate(lines: Sequence[LineFeature], pose: NDArray, covariance: NDArray,
              landmarks: NDArray, intervals: NDArray, sides: NDArray,
              settings: AssociationSettings) -> Association:
    """Match ``lines`` to active landmarks (see the module's description).

    :param pose: laser pose; ``covariance`` is ``P_AA``: the pose then the landmarks in order.
    :param landmarks: ``(J, 2)`` their lines; ``intervals`` ``(J, 2)`` their extents;
        ``sides`` ``(J,)`` the side bits they were seen from.
    """
    count = len(landmarks)
    if count == 0 or not lines:
        offsets = observe(landmarks, pose)[3] if count else np.zeros(0)
        return Association([], [], [], list(range(len(lines))), offsets)
    h, h_pose, h_line, offsets = observe(landmarks, pose)
    hph = _predicted_covariance(h_pose, h_line, covariance)                 # (J, 2, 2)
    z = np.array([(line.gamma, line.rho) for line in lines])                 # (L, 2)
    meas = np.array([line.covariance for line in lines])                     # (L, 2, 2)
    v_gamma = np.mod(z[:, 0:1] - h[None, :, 0] + math.pi, 2.0 * math.pi) - math.pi
    v_rho = z[:, 1:2] - h[None, :, 1]
    s = meas[:, None, :, :] + hph[None, :, :, :]                             # (L, J, 2, 2)
    a, b, d = s[..., 0, 0], s[..., 0, 1], s[..., 1, 1]
    distance = (d * v_gamma * v_gamma - 2.0 * b * v_gamma * v_rho + a * v_rho * v_rho) / \
        (a * d - b * b)
    gate = -2.0 * math.log1p(-settings.gate_probability)
    wide_gate = -2.0 * math.log1p(-settings.fallback_gate_probability)
    plausible = (np.abs(offsets) >= settings.min_facing)[None, :] & \
        _overlaps(lines, pose, covariance, landmarks, intervals, settings)
    other_side = (np.asarray(sides) & side_of(offsets)) == 0                  # (J,)
    angle_tol, rho_tol = settings.other_side_tolerance
    plausible &= ~other_side[None, :] | ((np.abs(v_gamma) < angle_tol) & (np.abs(v_rho) < rho_tol))
    matches, fallback, ambiguous, unmatched = [], [], [], []
    for k in range(len(lines)):
        options = np.flatnonzero(plausible[k] & (distance[k] < gate))
        wide = len(options) == 0
        if wide:
            options = np.flatnonzero(plausible[k] & (distance[k] < wide_gate))
        if len(options) == 0:
            unmatched.append(k)
            continue
        best = _resolve(options, distance[k], h, settings.ambiguity_margin)
        if best is None:
            ambiguous.append(k)
        else:
            matches.append((k, best))
            fallback.append(wide)
    return Association(matches, fallback, ambiguous, unmatched, offsets)


def _predicted_covariance(h_pose: NDArray, h_line: NDArray, cov: NDArray) -> NDArray:
    """``H P H^T`` per landmark: pose block, landmark block and their correlation."""
    count = len(h_pose)
    p_xx = cov[0:3, 0:3]
    p_xl = cov[0:3, 3:3 + 2 * count].reshape(3, count, 2).transpose(1, 0, 2)      # (J, 3, 2)
    diagonal = np.arange(count)
    p_ll = cov[3:, 3:].reshape(count, 2, count, 2)[diagonal, :, diagonal, :]      # (J, 2, 2)
    cross = h_pose @ p_xl @ h_line.transpose(0, 2, 1)
    return h_pose @ p_xx @ h_pose.transpose(0, 2, 1) + cross + cross.transpose(0, 2, 1) + \
        h_line @ p_ll @ h_line.transpose(0, 2, 1)


def _overlaps(lines: Sequence[LineFeature], pose: NDArray, cov: NDArray, landmarks: NDArray,
              intervals: NDArray, settings: AssociationSettings) -> NDArray:
    """``(L, J)``: whether each observed segment reaches each landmark's extent."""
    ends = np.array([(*line.start, *line.end) for line in lines]).reshape(-1, 2)      # (2L, 2)
    in_map = transform_points(pose, ends).reshape(-1, 2, 2)                           # (L, 2, 2)
    t = along(landmarks[None, None, :, 0], in_map[:, :, None, :])                    # (L, 2, J)
    low, high = t.min(axis=1), t.max(axis=1)
    reach = np.hypot(ends[:, 0], ends[:, 1]).reshape(-1, 2).max(axis=1)               # (L,)
    sigma_xy = math.sqrt(max(cov[0, 0] + cov[1, 1], 0.0))
    sigma_theta = math.sqrt(max(cov[2, 2], 0.0))
    slack = (settings.overlap_tolerance + 3.0 * (sigma_xy + sigma_theta * reach))[:, None]
    return (np.minimum(high, intervals[None, :, 1] + slack) -
            np.maximum(low, intervals[None, :, 0] - slack)) >= 0.0


def _resolve(options: NDArray, distance: NDArray, h: NDArray, margin: float) -> int | None:
    """The landmark a line with candidates ``options`` is, or None when ambiguous."""
    ranked = options[np.argsort(distance[options])]
    best = int(ranked[0])
    for other in ranked[1:]:
        if distance[other] - distance[best] >= margin:
            break
        turn = abs(math.remainder(float(h[other, 0] - h[best, 0]), 2.0 * math.pi))
        shift = float(h[other, 1] - h[best, 1])
        if turn < _SAME_ANGLE and abs(shift) < _SAME_DISTANCE:
            continue                                       # the same wall twice
        if turn < _PARALLEL and shift > 0.0:
            continue                                       # behind the best: hidden
        return None
    return best
