"""Range readings as points in the robot frame, for the avoidModule's laser and sonar.

A RangeFinder's info says where each beam starts and where it points: either ``sensor_positions``
(one pose per sensor: the sonar ring) or a uniform fan (``x_offset``, ``y_offset``,
``theta_offset``, ``theta_separation``: the laser, counter-clockwise from -90 degrees, WURDE 7.5).
:class:`Beams` keeps that as arrays; :meth:`Beams.points` turns one reading into (x, y) points in
metres, robot frame (x forward, y left), leaving out what is no echo (not finite, not positive).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

__all__ = ['Beams', 'wrap']


@dataclasses.dataclass(frozen=True)
class Beams:
    """Where each beam of a range sensor starts (``x``, ``y``) and its bearing (``theta``), robot
    frame; ``half_angle`` is a beam's half width (rad)."""

    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    half_angle: float = 0.0

    @classmethod
    def fan(cls, count: int, *, first: float, step: float, x: float = 0.0, y: float = 0.0,
            half_angle: float = 0.0) -> 'Beams':
        """A uniform fan of ``count`` beams from one point (a laser)."""
        theta = first + step * np.arange(count)
        return cls(np.full(count, x), np.full(count, y), theta, half_angle)

    @classmethod
    def ring(cls, poses: Sequence[tuple[float, float, float]], half_angle: float = 0.0) -> 'Beams':
        """One beam per sensor pose (x, y, theta) (a sonar ring)."""
        array = np.asarray(poses, dtype=float).reshape(-1, 3)
        return cls(array[:, 0], array[:, 1], array[:, 2], half_angle)

    def __len__(self) -> int:
        return len(self.theta)

    def points(self, ranges: Sequence[float] | np.ndarray) -> np.ndarray:
        """The echoes of one reading as an (N, 2) array (beams beyond the reading, or readings
        beyond the beams, are left out)."""
        r = np.asarray(ranges, dtype=float)[:len(self)]
        n = len(r)
        good = np.isfinite(r) & (r > 0.0)
        r, theta = r[good], self.theta[:n][good]
        return np.column_stack((self.x[:n][good] + r * np.cos(theta), self.y[:n][good] + r * np.sin(theta)))


def wrap(angle: float) -> float:
    """``angle`` in (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))
