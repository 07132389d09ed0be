"""Small helpers on line segments given by their end points (metres, any frame)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['clip_to_disc', 'distances_to_segments']


def distances_to_segments(point: ArrayLike, a: ArrayLike, b: ArrayLike) -> NDArray:
    """m from ``point`` ``(2,)`` to each segment ``a[i] b[i]`` (``(K, 2)`` each)."""
    p = np.asarray(point, dtype=np.float64).reshape(2)
    a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
    d = np.asarray(b, dtype=np.float64).reshape(-1, 2) - a
    length2 = np.einsum('ij,ij->i', d, d)
    u = np.clip(np.einsum('ij,ij->i', p - a, d) / np.where(length2 > 0.0, length2, 1.0), 0.0, 1.0)
    return np.hypot(*(a + u[:, None] * d - p).T)


def clip_to_disc(a: ArrayLike, b: ArrayLike, radius: float) -> NDArray | None:
    """``(2, 2)``: the part of segment ``ab`` within ``radius`` of the origin (None: no part)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    d = b - a
    qa, qb, qc = float(d @ d), 2.0 * float(a @ d), float(a @ a) - radius * radius
    disc = qb * qb - 4.0 * qa * qc
    if qa == 0.0 or disc <= 0.0:
        return None
    root = math.sqrt(disc)
    lo, hi = max(0.0, (-qb - root) / (2.0 * qa)), min(1.0, (-qb + root) / (2.0 * qa))
    if lo >= hi:
        return None
    return np.array([a + lo * d, a + hi * d])
