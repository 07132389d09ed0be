"""SE(2) pose algebra and line transforms, with the Jacobians the Kalman filter needs.

Conventions (REP-103): a pose is ``(x, y, theta)`` in metres and radians, theta counter-clockwise
from +x and wrapped to ``(-pi, pi]``.  ``compose(a, b)`` is ``a ⊕ b``: pose ``b`` given in the
frame of ``a``, expressed in ``a``'s parent frame; ``inverse(a)`` is ``⊖a``; ``relative(a, b)`` is
``⊖a ⊕ b``, where ``b`` is as seen from ``a`` (an odometry increment between two laser poses).

A line in normal form ``(gamma, rho)`` holds the points with ``x cos(gamma) + y sin(gamma) = rho``
and ``rho >= 0``: ``gamma`` is the direction of the perpendicular from the frame's origin to the
line.  Pose functions take scalars and return small numpy arrays; line functions are vectorised
over any number of lines.
"""

from __future__ import annotations

import math
from typing import overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    'compose', 'compose_jacobians', 'interpolate', 'inverse', 'inverse_jacobian', 'line_to_frame',
    'line_to_frame_jacobian', 'lines_in_frame', 'relative', 'relative_jacobians',
    'transform_points', 'wrap',
]

_TWO_PI = 2.0 * math.pi


@overload
def wrap(angle: float) -> float: ...


@overload
def wrap(angle: ArrayLike) -> NDArray | float: ...


def wrap(angle: ArrayLike) -> NDArray | float:
    """``angle`` wrapped to ``(-pi, pi]``.

    :param angle: radians, a scalar or an array.
    :returns: a float for a scalar (a 0-d array too), else an array of the same shape.
    """
    if isinstance(angle, (float, int)):
        return _wrap1(float(angle))
    wrapped = math.pi - np.mod(math.pi - np.asarray(angle, dtype=np.float64), _TWO_PI)
    return float(wrapped) if wrapped.ndim == 0 else wrapped


def _wrap1(angle: float) -> float:
    """Scalar :func:`wrap` without numpy (the hot paths of the filter call it per scan)."""
    return math.pi - math.fmod(math.fmod(math.pi - angle, _TWO_PI) + _TWO_PI, _TWO_PI)


def _xyt(pose: ArrayLike) -> list[float]:
    """``[x, y, theta]`` as Python floats (the pose functions compute with ``math``)."""
    return np.asarray(pose, dtype=np.float64).reshape(3).tolist()


def compose(a: ArrayLike, b: ArrayLike) -> NDArray:
    """``a ⊕ b``: pose ``b``, given in the frame of ``a``, in ``a``'s parent frame.

    :param a: pose ``(x, y, theta)`` in the parent frame, metres and radians.
    :param b: pose ``(x, y, theta)`` in ``a``'s frame.
    :returns: ``(x, y, theta)``, theta wrapped to ``(-pi, pi]``.
    """
    ax, ay, at = _xyt(a)
    bx, by, bt = _xyt(b)
    c, s = math.cos(at), math.sin(at)
    return np.array([ax + c * bx - s * by, ay + s * bx + c * by, _wrap1(at + bt)])


def compose_jacobians(a: ArrayLike, b: ArrayLike) -> tuple[NDArray, NDArray]:
    """``(d(a⊕b)/da, d(a⊕b)/db)``, each 3x3.

    :param a: pose ``(x, y, theta)`` in the parent frame.
    :param b: pose ``(x, y, theta)`` in ``a``'s frame.
    """
    at = _xyt(a)[2]
    bx, by, _ = _xyt(b)
    c, s = math.cos(at), math.sin(at)
    ja = np.array([[1.0, 0.0, -s * bx - c * by],
                   [0.0, 1.0, c * bx - s * by],
                   [0.0, 0.0, 1.0]])
    jb = np.array([[c, -s, 0.0],
                   [s, c, 0.0],
                   [0.0, 0.0, 1.0]])
    return ja, jb


def inverse(a: ArrayLike) -> NDArray:
    """``⊖a``: the parent frame's origin as seen from pose ``a``.

    :param a: pose ``(x, y, theta)`` in the parent frame.
    """
    ax, ay, at = _xyt(a)
    c, s = math.cos(at), math.sin(at)
    return np.array([-c * ax - s * ay, s * ax - c * ay, _wrap1(-at)])


def inverse_jacobian(a: ArrayLike) -> NDArray:
    """``d(⊖a)/da``, 3x3.

    :param a: pose ``(x, y, theta)`` in the parent frame.
    """
    ax, ay, at = _xyt(a)
    c, s = math.cos(at), math.sin(at)
    return np.array([[-c, -s, s * ax - c * ay],
                     [s, -c, c * ax + s * ay],
                     [0.0, 0.0, -1.0]])


def relative(a: ArrayLike, b: ArrayLike) -> NDArray:
    """``⊖a ⊕ b``: pose ``b`` as seen from pose ``a`` (both in the same parent frame).

    :param a: the reference pose ``(x, y, theta)``.
    :param b: the other pose ``(x, y, theta)``; ``relative(previous, now)`` is an odometry increment.
    """
    ax, ay, at = _xyt(a)
    bx, by, bt = _xyt(b)
    c, s = math.cos(at), math.sin(at)
    dx, dy = bx - ax, by - ay
    return np.array([c * dx + s * dy, -s * dx + c * dy, _wrap1(bt - at)])


def relative_jacobians(a: ArrayLike, b: ArrayLike) -> tuple[NDArray, NDArray]:
    """``(d(⊖a⊕b)/da, d(⊖a⊕b)/db)``, each 3x3.

    :param a: the reference pose ``(x, y, theta)``.
    :param b: the other pose ``(x, y, theta)``, in the same parent frame.
    """
    ax, ay, at = _xyt(a)
    bx, by, _ = _xyt(b)
    c, s = math.cos(at), math.sin(at)
    dx, dy = bx - ax, by - ay
    ja = np.array([[-c, -s, -s * dx + c * dy],
                   [s, -c, -c * dx - s * dy],
                   [0.0, 0.0, -1.0]])
    jb = np.array([[c, s, 0.0],
                   [-s, c, 0.0],
                   [0.0, 0.0, 1.0]])
    return ja, jb


def transform_points(pose: ArrayLike, points: ArrayLike) -> NDArray:
    """``(N, 2)`` points given in the frame at ``pose``, expressed in its parent frame.

    :param pose: the frame's pose ``(x, y, theta)`` in the parent frame.
    :param points: ``(N, 2)`` (or anything of ``2N`` values) metres in the frame at ``pose``.
    """
    x, y, t = _xyt(pose)
    xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    c, s = math.cos(t), math.sin(t)
    return np.column_stack([x + c * xy[:, 0] - s * xy[:, 1], y + s * xy[:, 0] + c * xy[:, 1]])


def line_to_frame(gamma: ArrayLike, rho: ArrayLike, pose: ArrayLike) -> tuple[NDArray | float, NDArray]:
    """Lines ``(gamma, rho)`` of the parent frame as seen from a sensor at ``pose``.

    ``gamma' = gamma - theta`` and ``rho' = rho - x cos(gamma) - y sin(gamma)``; where ``rho'``
    comes out negative (the sensor is on the other side of the line than the parent's origin) the
    normal is flipped: ``rho' -> -rho'``, ``gamma' -> gamma' + pi``.

    :param gamma: rad, the lines' normal directions (scalar or array).
    :param rho: m, their distances from the parent's origin.
    :param pose: the sensor's pose ``(x, y, theta)`` in the parent frame.
    :returns: ``(gamma', rho')`` arrays, ``gamma'`` wrapped (a float for a scalar ``gamma``), ``rho' >= 0``.
    """
    g, r, _, _ = lines_in_frame(gamma, rho, pose)
    return wrap(g), r


def line_to_frame_jacobian(gamma: ArrayLike, rho: ArrayLike, pose: ArrayLike) -> NDArray:
    """``d(gamma', rho')/d(x, y, theta)`` of :func:`line_to_frame`.

    The flip changes the sign of the ``rho'`` row only (``gamma' + pi`` moves with theta the same).

    :param gamma: rad, the lines' normal directions (scalar or array).
    :param rho: m, their distances from the parent's origin.
    :param pose: the sensor's pose ``(x, y, theta)`` in the parent frame.
    :returns: ``(N, 2, 3)``, each ``[[0, 0, -1], [hx, hy, 0]]``.
    """
    _, _, hx, hy = lines_in_frame(np.atleast_1d(gamma), np.atleast_1d(rho), pose)
    jac = np.zeros((len(hx), 2, 3))
    jac[:, 0, 2] = -1.0
    jac[:, 1, 0] = hx
    jac[:, 1, 1] = hy
    return jac


def lines_in_frame(gamma: ArrayLike, rho: ArrayLike, pose: ArrayLike, *,
                   cos_gamma: NDArray | None = None,
                   sin_gamma: NDArray | None = None) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """:func:`line_to_frame` and its Jacobian in one pass, for the matcher's inner loop.

    :param gamma: rad, the lines' normal directions.
    :param rho: m, their distances from the parent's origin.
    :param pose: the sensor's pose ``(x, y, theta)`` in the parent frame.
    :param cos_gamma: ``cos(gamma)`` if already known; None: computed.
    :param sin_gamma: ``sin(gamma)`` if already known; None: computed.
    :returns: ``(gamma', rho', hx, hy)``: ``gamma'`` *not* wrapped, and the Jacobian's second row
        ``[hx, hy, 0]`` (its first is always ``[0, 0, -1]``).
    """
    g = np.asarray(gamma, dtype=np.float64)
    x, y, t = _xyt(pose)
    cg = np.cos(g) if cos_gamma is None else cos_gamma
    sg = np.sin(g) if sin_gamma is None else sin_gamma
    r = np.asarray(rho, dtype=np.float64) - x * cg - y * sg
    sign = np.where(r < 0.0, 1.0, -1.0)
    return g - t + (sign + 1.0) * (0.5 * math.pi), np.abs(r), sign * cg, sign * sg


def interpolate(a: ArrayLike, b: ArrayLike, f: float) -> NDArray:
    """The pose a fraction ``f`` of the way from ``a`` to ``b`` (the angle the short way round).

    :param a: pose ``(x, y, theta)`` at ``f = 0``.
    :param b: pose ``(x, y, theta)`` at ``f = 1``.
    :param f: the fraction; outside [0, 1] it extrapolates.
    """
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return np.array([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), _wrap1(a[2] + f * _wrap1(b[2] - a[2]))])
