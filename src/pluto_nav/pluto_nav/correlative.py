"""Correlative scan matching (Olson, "Real-time correlative scan matching", ICRA 2009): every pose
of a window, on a grid of translations and rotations, scored by the likelihood field under the
scan's points.

It finds the right pose from a guess that is off by more than any local method can mend (a
stale odometry reading, a loop closed after a long way round) and says how good the best pose is
compared with the rest of the window, which is what tells a true loop closure from a look-alike.
The search is exhaustive over the window, so its answer does not depend on where it starts; its
precision is the grid's, and :mod:`.icp` refines it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from .geometry import wrap
from .point_map import PointMap

__all__ = ['Candidate', 'Window', 'guesses', 'search', 'search_guesses']


@dataclasses.dataclass(frozen=True)
class Window:
    """Half-widths of a search window round a guess, and its steps.

    :ivar xy: m, half-width in x and in y.
    :ivar theta: rad, half-width in rotation.
    :ivar theta_step: rad between two rotations tried.
    :ivar factor: cells of the map's field per translation step (1: its resolution).
    """

    xy: float
    theta: float
    theta_step: float = math.radians(1.0)
    factor: int = 1


@dataclasses.dataclass(frozen=True)
class Candidate:
    """A pose of the window and its score: the mean likelihood under the scan's points (0 to 1)."""

    score: float
    pose: tuple[float, float, float]

    def distance(self, other: Candidate) -> tuple[float, float]:
        """m and rad between the two poses."""
        return (math.hypot(self.pose[0] - other.pose[0], self.pose[1] - other.pose[1]),
                abs(float(wrap(self.pose[2] - other.pose[2]))))


def search(point_map: PointMap, points: NDArray, guess: NDArray, window: Window, *,
           per_rotation: int = 1) -> list[Candidate]:
    """The best ``per_rotation`` translations of each rotation of ``window`` round ``guess``,
    best first.

    :param points: ``(N, 2)`` the scan's points in its own frame.
    :param guess: the scan's pose ``(x, y, theta)`` in the map's frame, the window's centre.
    """
    field = point_map.field(window.factor)
    step = point_map.resolution * window.factor
    reach = max(0, int(round(window.xy / step)))
    offsets = np.arange(-reach, reach + 1)
    rows, cols = field.shape
    turns = max(0, int(math.floor(window.theta / window.theta_step + 1e-9)))
    theta = guess[2] + window.theta_step * np.arange(-turns, turns + 1)            # (A,)
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    x = guess[0] + c * points[:, 0] - s * points[:, 1]                              # (A, N)
    y = guess[1] + s * points[:, 0] + c * points[:, 1]
    ix = np.floor((x - point_map.origin[0]) / step).astype(np.intp)
    iy = np.floor((y - point_map.origin[1]) / step).astype(np.intp)
    cx = np.clip(ix[:, None, :] + offsets[None, :, None], 0, rows - 1)             # (A, O, N)
    cy = np.clip(iy[:, None, :] + offsets[None, :, None], 0, cols - 1)
    flat = field.reshape(-1)
    scores = flat[cx[:, :, None, :] * cols + cy[:, None, :, :]].sum(axis=3) / len(points)  # (A, O, O)
    per_angle = scores.reshape(len(theta), -1)
    order = np.argsort(per_angle, axis=1)[:, ::-1][:, :per_rotation]
    found: list[Candidate] = []
    for a in range(len(theta)):
        for flat_index in order[a]:
            i, j = divmod(int(flat_index), len(offsets))
            found.append(Candidate(float(per_angle[a, flat_index]),
                                   (float(guess[0] + offsets[i] * step), float(guess[1] + offsets[j] * step),
                                    float(wrap(theta[a])))))
    found.sort(key=lambda candidate: -candidate.score)
    return found


def guesses(odometry: NDArray, previous: NDArray, last_step: NDArray, *, apart_xy: float, apart_theta: float
            ) -> list[NDArray]:
    """Where a scan may be: the odometry's guess first, then the last matched motion again and
    standing still, each only if it differs from the ones before by ``apart_xy`` (m) or
    ``apart_theta`` (rad).  Real odometry lags and then catches up in one jump, or jumps by itself
    (a reset, a glitch): one of the three is near the truth far more often than the first alone."""
    from .geometry import compose
    found = [np.asarray(odometry, dtype=np.float64)]
    for other in (compose(previous, last_step), np.asarray(previous, dtype=np.float64)):
        if all(math.hypot(other[0] - g[0], other[1] - g[1]) > apart_xy or abs(wrap(other[2] - g[2])) > apart_theta
               for g in found):
            found.append(other)
    return found


def search_guesses(point_map: PointMap, points: NDArray, tries: list[tuple[NDArray, Window]]) -> Candidate:
    """The best pose over the windows round several guesses."""
    return max((search(point_map, points, guess, window)[0] for guess, window in tries),
               key=lambda candidate: candidate.score)
