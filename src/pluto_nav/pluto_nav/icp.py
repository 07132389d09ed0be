"""Point-to-line ICP of a scan against a :class:`.point_map.PointMap`, with the information of the
result.

Each scan point is paired with its nearest map point and the residual is its distance to the
tangent line there (the map point's normal), the error metric of Censi's PL-ICP, which converges
in a few steps on the walls of buildings.  Gauss-Newton with Huber weights: a chair that moved or
a person walking by costs a bounded weight, not a skewed pose.

The information matrix (inverse covariance) of the pose is ``J^T J / s^2`` over the pairs within
``inlier`` of the map, ``s^2`` their residuals' variance (at least ``floor``): it is large across
a corridor's walls and near zero along them, which is what a pose graph must know of a match made
in a corridor.  Neighbouring beams are not independent, so it is over-confident by a roughly
constant factor; :mod:`.graph_slam` scales it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from .geometry import transform_points, wrap
from .point_map import PointMap

__all__ = ['IcpResult', 'IcpSettings', 'refine']


@dataclasses.dataclass(frozen=True)
class IcpSettings:
    """Tunables of :func:`refine` (defaults in brackets)."""

    #: Gauss-Newton steps at most [20].
    iterations: int = 20
    #: m: pairs farther apart are not used [0.3].
    max_distance: float = 0.3
    #: m: residuals beyond this get Huber's smaller weight [0.05].
    huber: float = 0.05
    #: m: a point within this of the map fits it (the inlier fraction, the information) [0.1].
    inlier: float = 0.1
    #: m: the residuals' standard deviation is taken as at least this [0.01].
    floor: float = 0.01
    #: Fewest pairs for a result [10].
    min_pairs: int = 10


@dataclasses.dataclass(frozen=True)
class IcpResult:
    """:ivar pose: the scan's pose in the map's frame.
    :ivar information: 3x3, of ``pose`` (x, y in the map's frame, theta).
    :ivar inliers: fraction of the scan's points within ``inlier`` of the map.
    :ivar ok: False when too few points could be paired (pose is then the start).
    """

    pose: NDArray
    information: NDArray
    inliers: float
    ok: bool


def _pairs(point_map: PointMap, points: NDArray, pose: NDArray, max_distance: float
           ) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Residuals, Jacobians, distances of the paired points, and which points were paired."""
    world = transform_points(pose, points)
    distance, index = point_map.nearest(world, max_distance)
    paired = np.isfinite(distance)
    src = world[paired]
    normal = point_map.normals[index[paired]]
    residual = np.einsum('ij,ij->i', src - point_map.points[index[paired]], normal)
    arm = src - pose[:2]
    jacobian = np.column_stack([normal[:, 0], normal[:, 1],
                                arm[:, 0] * normal[:, 1] - arm[:, 1] * normal[:, 0]])
    return residual, jacobian, distance[paired], paired


def refine(point_map: PointMap, points: NDArray, start: NDArray,
           settings: IcpSettings = IcpSettings()) -> IcpResult:
    """Point-to-line ICP from ``start`` (see the module's description)."""
    pose = np.asarray(start, dtype=np.float64).copy()
    for _ in range(settings.iterations):
        residual, jacobian, _, _ = _pairs(point_map, points, pose, settings.max_distance)
        if len(residual) < settings.min_pairs:
            return IcpResult(np.asarray(start, dtype=np.float64), np.zeros((3, 3)), 0.0, False)
        size = np.abs(residual)
        weight = np.where(size < settings.huber, 1.0, settings.huber / np.maximum(size, 1e-12))
        hessian = jacobian.T @ (jacobian * weight[:, None])
        gradient = jacobian.T @ (weight * residual)
        try:
            step = -np.linalg.solve(hessian + 1e-9 * np.eye(3), gradient)
        except np.linalg.LinAlgError:
            break
        pose = np.array([pose[0] + step[0], pose[1] + step[1], wrap(pose[2] + step[2])])
        if max(abs(step[0]), abs(step[1])) < 1e-4 and abs(step[2]) < 1e-5:
            break
    residual, jacobian, distance, paired = _pairs(point_map, points, pose, settings.inlier)
    if len(residual) < settings.min_pairs:
        return IcpResult(pose, np.zeros((3, 3)), float(len(residual)) / max(1, len(points)), False)
    variance = max(float(residual @ residual) / max(1, len(residual) - 3), settings.floor ** 2)
    return IcpResult(pose, jacobian.T @ jacobian / variance, float(paired.mean()), True)
