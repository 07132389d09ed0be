"""A wall as a SLAM landmark: its infinite line ``(gamma, rho)`` in the map frame, and how a laser
sees it.

The line holds the points with ``x cos(gamma) + y sin(gamma) = rho``.  Unlike the observed lines
(:mod:`.lines`, ``rho >= 0``) a landmark's ``rho`` is *signed*: ``(gamma, rho)`` and
``(gamma + pi, -rho)`` are the same line, and a landmark keeps the form it was born with, so the
state never jumps when an update carries a line across the map's origin.  Positions along the
line, ``t``, are measured along ``(-sin gamma, cos gamma)`` from the foot of the perpendicular
from the origin (as :class:`.wall_map.WallMap`'s extents).

Jacobians are for the filter: a laser at ``(x, y, theta)`` sees the line at

    ``rho' = |d|``, ``gamma' = gamma - theta (+ pi when d < 0)``,
    ``d = rho - x cos gamma - y sin gamma``

(``d`` is the signed offset of the line from the laser: its sign says which side the laser is on).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .geometry import wrap

__all__ = ['along', 'align', 'initialise', 'intersection', 'observe', 'point_at']


def observe(lines: ArrayLike, pose: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Landmark lines ``(J, 2)`` as seen by a laser at ``pose``.

    :returns: ``(z, h_pose, h_line, offset)``: the predicted ``(gamma', rho')`` ``(J, 2)``, their
        Jacobians with respect to the pose ``(J, 2, 3)`` and to the landmark ``(J, 2, 2)``, and the
        signed offset ``d`` ``(J,)``.
    """
    lm = np.asarray(lines, dtype=np.float64).reshape(-1, 2)
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64).reshape(3))
    g = lm[:, 0]
    c, s = np.cos(g), np.sin(g)
    offset = lm[:, 1] - x * c - y * s
    sign = np.where(offset < 0.0, -1.0, 1.0)
    z = np.column_stack([wrap(g - theta + np.where(offset < 0.0, math.pi, 0.0)), np.abs(offset)])
    h_pose = np.zeros((len(lm), 2, 3))
    h_pose[:, 0, 2] = -1.0
    h_pose[:, 1, 0] = -sign * c
    h_pose[:, 1, 1] = -sign * s
    h_line = np.zeros((len(lm), 2, 2))
    h_line[:, 0, 0] = 1.0
    h_line[:, 1, 0] = sign * (x * s - y * c)
    h_line[:, 1, 1] = sign
    return z, h_pose, h_line, offset


def initialise(gamma: float, rho: float, pose: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
    """The landmark of a line ``(gamma, rho)`` seen by a laser at ``pose`` (``rho >= 0`` form).

    :returns: ``(line, g_pose, g_z)``: the map line ``(2,)`` and its Jacobians with respect to the
        pose ``(2, 3)`` and to the observed line ``(2, 2)``.
    """
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64).reshape(3))
    g = float(wrap(gamma + theta))
    c, s = math.cos(g), math.sin(g)
    r = rho + x * c + y * s
    d = -x * s + y * c
    g_pose = np.array([[0.0, 0.0, 1.0], [c, s, d]])
    g_z = np.array([[1.0, 0.0], [d, 1.0]])
    if r < 0.0:
        g, r = float(wrap(g + math.pi)), -r
        g_pose[1] *= -1.0
        g_z[1] *= -1.0
    return np.array([g, r]), g_pose, g_z


def align(reference: ArrayLike, line: ArrayLike) -> tuple[NDArray, float]:
    """``line`` in the form closest to ``reference`` (``(gamma, rho)`` or ``(gamma + pi, -rho)``).

    :returns: ``(line, sign)``: ``sign`` is -1 when the form was turned (then ``t`` along the line
        and the Jacobian's ``rho`` row change sign too).
    """
    g0 = float(np.asarray(reference, dtype=np.float64).reshape(2)[0])
    g, r = (float(v) for v in np.asarray(line, dtype=np.float64).reshape(2))
    if abs(float(wrap(g - g0))) > math.pi / 2:
        return np.array([float(wrap(g + math.pi)), -r]), -1.0
    return np.array([g, r]), 1.0


def along(gamma: ArrayLike, points: ArrayLike) -> NDArray:
    """``t`` of points ``(..., 2)`` along lines of direction ``gamma`` (broadcast)."""
    p = np.asarray(points, dtype=np.float64)
    g = np.asarray(gamma, dtype=np.float64)
    return -np.sin(g) * p[..., 0] + np.cos(g) * p[..., 1]


def point_at(gamma: ArrayLike, rho: ArrayLike, t: ArrayLike) -> NDArray:
    """The points ``(..., 2)`` at ``t`` along lines ``(gamma, rho)`` (broadcast)."""
    g = np.asarray(gamma, dtype=np.float64)
    r = np.asarray(rho, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    c, s = np.cos(g), np.sin(g)
    return np.stack([r * c - t * s, r * s + t * c], axis=-1)


def intersection(gamma: ArrayLike, rho: ArrayLike, other_gamma: ArrayLike,
                 other_rho: ArrayLike) -> tuple[NDArray, NDArray]:
    """Where lines cross other lines (broadcast): ``(t, sine)``, ``t`` along the first line and
    ``sine`` the sine of the angle between them (``t`` is ``inf`` for parallel lines)."""
    g, r = np.asarray(gamma, dtype=np.float64), np.asarray(rho, dtype=np.float64)
    gk, rk = np.asarray(other_gamma, dtype=np.float64), np.asarray(other_rho, dtype=np.float64)
    sine = np.sin(gk - g)
    with np.errstate(divide='ignore', invalid='ignore'):
        t = np.where(sine != 0.0, (rk - r * np.cos(gk - g)) / np.where(sine != 0.0, sine, 1.0),
                     np.inf)
    return t, sine
