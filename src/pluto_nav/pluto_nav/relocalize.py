"""Re-localization of the line filter against the map when its pose stops fitting the scans.

The poseModule's Kalman filter (:class:`pluto_nav.pose_filter.PoseFilter`) matches lines to walls
inside gates drawn from its own covariance.  A pose that is off by more than those gates allow (a
base restart's gap reckoned on a wrong heading, a filter that took in a bad scan) finds few walls,
or the wrong ones, and the filter can hold the error for a long time: a soak saw the Pose 14
degrees off for 27 s (issue 38, which asks that the poseModule re-localize at once against the
map).

The check is cheap and runs on every scan: the fraction of the scan's points within
:data:`FIT_DISTANCE` of a wall at the filter's pose.  After :data:`STRIKES` scans in a row below
:data:`SUSPECT_FIT`, the scan is searched for over a window round the pose (:mod:`.correlative`,
then :mod:`.icp`), at most every :data:`SEARCH_PERIOD` scans; the pose found replaces the filter's
only if the scan fits it clearly better (:data:`BETTER_BY` more of its points, and at least
:data:`GOOD_FIT`).  Furniture and people, which are not in the map, lower the fit at the true pose
too, but no other pose fits them better, so they cost a search now and then and never a jump; nor
does a corridor, where poses along it fit alike.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .correlative import Window, search
from .estimation import Scan
from .icp import refine
from .point_map import PointMap, voxel_filter

__all__ = ['BETTER_BY', 'FIT_DISTANCE', 'GOOD_FIT', 'RELOCALIZED_SIGMA', 'Relocalization', 'Relocalizer',
           'STRIKES', 'SUSPECT_FIT', 'WINDOW']

#: m: a scan point this near a wall fits the map.
FIT_DISTANCE = 0.15
#: Below this fraction of fitting points a scan is suspect.
SUSPECT_FIT = 0.6
#: Suspect scans in a row before a search.
STRIKES = 3
#: Scans between two searches while the scans stay suspect.
SEARCH_PERIOD = 5
#: A pose found must fit this many more of the scan's points (a fraction) than the filter's ...
BETTER_BY = 0.25
#: ... and at least this fraction.
GOOD_FIT = 0.7
#: The window searched round the filter's pose: m each way, rad each way.
WINDOW = Window(xy=0.6, theta=math.radians(25.0), theta_step=math.radians(1.0))
#: Standard deviations (m, m, rad) the filter restarts with at a pose found.
RELOCALIZED_SIGMA = (0.05, 0.05, math.radians(2.0))
#: m: the scan's points are thinned to one per cell of this size.
VOXEL = 0.1
#: Fewest points a scan needs to be judged.
MIN_POINTS = 20


@dataclasses.dataclass(frozen=True)
class Relocalization:
    """A pose found for a scan that did not fit the filter's: where the filter was, where the
    scan fits, and the fraction of its points that fit each."""

    before: tuple[float, float, float]
    after: tuple[float, float, float]
    fit_before: float
    fit_after: float

    def describe(self) -> str:
        dx, dy = self.after[0] - self.before[0], self.after[1] - self.before[1]
        turn = math.degrees(math.remainder(self.after[2] - self.before[2], math.tau))
        return (f'{math.hypot(dx, dy):.2f} m and {turn:+.1f} deg from the filter\'s pose; '
                f'{100 * self.fit_before:.0f} % of the scan fitted the map there, {100 * self.fit_after:.0f} % here')


class Relocalizer:
    """Watches the fit of each scan at the filter's pose and searches when it stays poor.

    :param map_points: ``(N, 2)`` points along the map's walls (:func:`.localizers.wall_points`).
    """

    def __init__(self, map_points: ArrayLike) -> None:
        self.map = PointMap(voxel_filter(map_points, 0.05), resolution=0.1, sigma=0.1)
        self.strikes = 0
        self.since_search = SEARCH_PERIOD
        self.searches = 0
        self.found: list[Relocalization] = []

    def check(self, scan: Scan, pose: ArrayLike) -> Relocalization | None:
        """Judge ``scan`` at the laser pose ``pose``; a :class:`Relocalization` when the scan fits
        another pose of the window clearly better (the caller restarts its filter there)."""
        points = scan.points(VOXEL)
        if len(points) < MIN_POINTS:
            return None
        at = np.asarray(pose, dtype=np.float64)
        fit = self.fit(points, at)
        self.since_search += 1
        if fit >= SUSPECT_FIT:
            self.strikes = 0
            return None
        self.strikes += 1
        if self.strikes < STRIKES or self.since_search < SEARCH_PERIOD:
            return None
        self.since_search = 0
        self.searches += 1
        best = search(self.map, points, at, WINDOW)[0]
        result = refine(self.map, points, np.array(best.pose))
        if not result.ok:
            return None
        fit_after = self.fit(points, result.pose)
        if fit_after < GOOD_FIT or fit_after < fit + BETTER_BY:
            return None
        self.strikes = 0
        found = Relocalization(_triple(at), _triple(result.pose), fit, fit_after)
        self.found.append(found)
        del self.found[:-100]
        return found

    def fit(self, points: NDArray, pose: ArrayLike) -> float:
        """The fraction of ``points`` (the scan's frame) within :data:`FIT_DISTANCE` of a wall
        when the scan is at ``pose``."""
        x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64)[:3])
        c, s = math.cos(theta), math.sin(theta)
        world = np.column_stack([x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1]])
        distance, _ = self.map.nearest(world, FIT_DISTANCE)
        return float(np.isfinite(distance).mean())

    @staticmethod
    def covariance() -> NDArray:
        """The covariance a filter restarts with at a pose found."""
        return np.diag(np.square(RELOCALIZED_SIGMA))


def _triple(pose: ArrayLike) -> tuple[float, float, float]:
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64)[:3])
    return x, y, theta
