"""Pluto's "find the longest wall in front of the robot" (Pluto 7.1).

The poseModule answers ``element[1] = 2`` with the number of scan points in the wall and six
parameters: ``gamma``, ``rho`` and their 2x2 covariance.  Pluto's pose_i uses it to calibrate the
odometry (drive at a wall, turn in front of it) and to measure a wall's angle and distance.

*In front* means here: the wall faces the laser within ``front_angle`` (45 degrees) of straight
ahead, i.e. the perpendicular from the laser to the wall's line, ``gamma``, is within
``±front_angle`` of the laser's x axis.  Such a wall is ahead of the laser, never beside or
behind it, and the laser's straight-ahead beam meets its line, at ``rho / cos(gamma)``.
*Longest* means the most scan points, as the seed counts them; a tie goes to the nearer wall.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

from numpy.typing import NDArray

from .lines import LineFeature

__all__ = ['DEFAULT_FRONT_ANGLE', 'FoundWall', 'find_wall']

#: rad: how far from straight ahead a wall's normal may point and still be "in front" [45 deg].
DEFAULT_FRONT_ANGLE = math.radians(45.0)


@dataclasses.dataclass(frozen=True, eq=False)
class FoundWall:
    """The wall :func:`find_wall` chose, in the laser frame."""

    points: int
    gamma: float
    rho: float
    covariance: NDArray
    line: LineFeature

    def parameters(self) -> list[float]:
        """The six numbers of the seed's data vector: ``gamma, rho, c_gg, c_gr, c_rg, c_rr``."""
        return [self.gamma, self.rho, *(float(v) for v in self.covariance.reshape(4))]


def find_wall(lines: Sequence[LineFeature], *,
              front_angle: float = DEFAULT_FRONT_ANGLE) -> FoundWall | None:
    """The line with the most points among those in front (see the module's description).

    :param lines: the scan's lines in the laser frame.
    :param front_angle: rad; a line is in front when its normal is within this of straight ahead
        (in (0, pi/2)).
    :returns: the wall, or None when no line is in front.
    :raises ValueError: ``front_angle`` outside (0, pi/2).
    """
    if not 0.0 < front_angle < math.pi / 2:
        raise ValueError(f'front_angle must be in (0, pi/2), not {front_angle}')
    front = [line for line in lines if abs(line.gamma) <= front_angle]
    if not front:
        return None
    best = max(front, key=lambda line: (line.points, -line.rho))
    return FoundWall(points=best.points, gamma=best.gamma, rho=best.rho,
                     covariance=best.covariance.copy(), line=best)
