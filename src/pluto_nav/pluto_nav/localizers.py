"""The poseModule's two methods (``-e``): where the laser is in an a-priori map.

- :class:`LineLocalizer` (``lines``, the default; Pluto 7.1): the scan's straight walls matched to
  the map's walls in an extended Kalman filter (:class:`.pose_filter.PoseFilter`).  Exact and
  cheap where a building is made of long walls, as the simulator's maps are.
- :class:`ScanLocalizer` (``scans``): every laser point matched to the map (a correlative search
  then point-to-line ICP, as the graph SLAM's front end), the match fused with the odometry's
  prediction by their information.  For real buildings, where clutter, glass and furniture leave
  too few clean lines, and for maps that are occupancy grids (a SLAM's, CARMEN's, a ROS map's).

Both take the :class:`.estimation.Method` interface, so the poseModule and ``offline_nav`` run
either the same way.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .correlative import Window, guesses, search_guesses
from .estimation import Scan
from .geometry import compose, compose_jacobians, relative, wrap
from .icp import refine
from .matching import MatchSettings
from .point_map import PointMap, voxel_filter
from .pose_filter import PoseFilter
from .relocalize import Relocalization, Relocalizer
from .wall_map import WallMap

__all__ = ['LineLocalizer', 'ScanLocalizer', 'ScanLocalizerSettings', 'wall_points']


class LineLocalizer:
    """Pluto 7.1's poseModule method: lines to walls in a Kalman filter."""

    def __init__(self, wall_map: WallMap, settings: Callable[[], MatchSettings] | None = None, *,
                 relocalize: bool = True, on_relocalize: Callable[[Relocalization], None] | None = None) -> None:
        """A :class:`.pose_filter.PoseFilter` against ``wall_map``.

        :param wall_map: the a-priori map's walls.
        :param settings: called before each update for the matcher's current settings (the poseModule's
            tunables); None: the filter's defaults.
        :param relocalize: restart the filter where the scans fit the map when they stop fitting
            its pose (:mod:`.relocalize`).
        :param on_relocalize: called with each such restart (the poseModule logs it).
        """
        self.wall_map = wall_map
        self.filter = PoseFilter()
        self._settings = settings
        self.relocalizer: Relocalizer | None = None
        if relocalize and len(wall_map.walls):
            try:
                self.relocalizer = Relocalizer(wall_points(wall_map.walls))
            except ValueError:
                self.relocalizer = None       # too small a map to judge a scan by
        self._on_relocalize = on_relocalize

    @property
    def pose(self) -> NDArray:
        return self.filter.pose

    @property
    def covariance(self) -> NDArray:
        return self.filter.covariance

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """Start from ``pose`` with ``covariance`` (:meth:`.PoseFilter.set_pose`).

        :param pose: the laser pose ``(x, y, theta)`` in the map frame.
        :param covariance: 3x3, symmetric positive definite.
        """
        self.filter.set_pose(pose, covariance)

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        """Move by the odometry ``increment`` (:meth:`.PoseFilter.predict`).

        :param increment: ``(dx, dy, dtheta)`` in the previous laser frame.
        :param increment_covariance: its 3x3 covariance.
        """
        self.filter.predict(increment, increment_covariance)

    def update(self, scan: Scan) -> bool:
        """Correct the pose with the scan's lines matched to the map's walls.

        :param scan: the scan, in the laser frame.
        :returns: whether any line matched a wall, or the filter was restarted where the scan
            fits the map (:mod:`.relocalize`).
        """
        if self._settings is not None:
            self.filter.settings = self._settings()
        matched = self.filter.update(scan.lines(), self.wall_map).matches > 0
        found = None if self.relocalizer is None else self.relocalizer.check(scan, self.filter.pose)
        if found is None:
            return matched
        self.filter.set_pose(found.after, self.relocalizer.covariance())  # type: ignore[union-attr]
        if self._on_relocalize is not None:
            self._on_relocalize(found)
        return True


def wall_points(walls: ArrayLike, spacing: float = 0.025) -> NDArray:
    """Points every ``spacing`` metres along each wall, ends included.

    :param walls: ``(N, 4)`` segments ``x1, y1, x2, y2``, metres.
    :param spacing: m between points (at most; each wall is cut into equal steps).
    :returns: ``(M, 2)`` points.
    """
    segments = np.asarray(walls, dtype=np.float64).reshape(-1, 4)
    points = []
    for x1, y1, x2, y2 in segments:
        count = max(2, int(math.ceil(math.hypot(x2 - x1, y2 - y1) / spacing)) + 1)
        t = np.linspace(0.0, 1.0, count)
        points.append(np.column_stack([x1 + t * (x2 - x1), y1 + t * (y2 - y1)]))
    return np.vstack(points) if points else np.zeros((0, 2))


@dataclasses.dataclass(frozen=True)
class ScanLocalizerSettings:
    """Tunables of :class:`ScanLocalizer` (defaults in brackets)."""

    #: m: readings used [0.1, 30].
    min_range: float = 0.1
    max_range: float = 30.0
    #: m: the scan's points are thinned to one per cell of this size [0.1].
    scan_voxel: float = 0.1
    #: The likelihood field: m per cell [0.1] and spread (m) [0.1].
    field_resolution: float = 0.1
    field_sigma: float = 0.1
    #: The search window is three standard deviations of the prediction, at least these (m, rad)
    #: [0.3, 6 deg] and at most these [1.5, 30 deg].
    window_min: tuple[float, float] = (0.3, math.radians(6.0))
    window_max: tuple[float, float] = (1.5, math.radians(30.0))
    #: A match counts when this fraction of the scan's points fits the map [0.5]: furniture and
    #: people are not in the map.
    min_inliers: float = 0.5
    #: Guesses beside the odometry's, as the graph SLAM's front end (m, rad) [0.1, 5 deg].
    hypothesis_xy: float = 0.1
    hypothesis_theta: float = math.radians(5.0)
    #: Factor on ICP's information [0.1] and standard deviations added to the match's covariance
    #: (m, rad) [0.01, 0.3 deg], as the graph SLAM's.
    information_scale: float = 0.1
    floor: tuple[float, float] = (0.01, math.radians(0.3))


class ScanLocalizer:
    """Scan-to-map matching fused with the odometry (see the module's description).

    :param map_points: ``(N, 2)`` points of the map: its walls sampled (:func:`wall_points`) or
        an occupancy grid's occupied cells.
    """

    def __init__(self, map_points: ArrayLike, settings: ScanLocalizerSettings = ScanLocalizerSettings()) -> None:
        """The map's points, thinned to one per 5 cm, as a :class:`.point_map.PointMap`.

        :param map_points: ``(N, 2)`` points of the map: its walls sampled (:func:`wall_points`) or
            an occupancy grid's occupied cells.
        :param settings: the tunables (:class:`ScanLocalizerSettings`).
        """
        self.settings = settings
        self.map = PointMap(voxel_filter(map_points, 0.05), resolution=settings.field_resolution,
                            sigma=settings.field_sigma)
        self._pose = np.zeros(3)
        self._cov = np.eye(3)
        self._last = np.zeros(3)         # the pose after the last update
        self._step = np.zeros(3)         # the motion between the last two updates
        self.inliers = 0.0

    @property
    def pose(self) -> NDArray:
        return self._pose.copy()

    @property
    def covariance(self) -> NDArray:
        return self._cov.copy()

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """Start from ``pose`` with ``covariance``.

        :param pose: the laser pose ``(x, y, theta)`` in the map frame.
        :param covariance: its 3x3 covariance.
        """
        self._pose = compose(np.asarray(pose, dtype=np.float64), (0.0, 0.0, 0.0))
        self._cov = np.asarray(covariance, dtype=np.float64).reshape(3, 3).copy()
        self._last, self._step = self._pose.copy(), np.zeros(3)

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        """Move by the odometry ``increment`` with its covariance.

        :param increment: ``(dx, dy, dtheta)`` in the previous laser frame.
        :param increment_covariance: its 3x3 covariance.
        """
        j_pose, j_inc = compose_jacobians(self._pose, increment)
        self._pose = compose(self._pose, increment)
        cov = j_pose @ self._cov @ j_pose.T + j_inc @ np.asarray(increment_covariance).reshape(3, 3) @ j_inc.T
        self._cov = 0.5 * (cov + cov.T)

    def update(self, scan: Scan) -> bool:
        """Match the scan to the map round the prediction and fuse the match with it.

        :param scan: the scan, in the laser frame.
        :returns: whether the scan matched (enough points, and ``min_inliers`` of them fitting); the
            pose is unchanged when not.
        """
        s = self.settings
        sample = scan.points(s.scan_voxel, min_range=s.min_range, max_range=s.max_range)
        if len(sample) < 20:
            return False
        sigma = np.sqrt(np.maximum(np.diag(self._cov), 0.0))
        window = Window(float(np.clip(3 * max(sigma[0], sigma[1]), s.window_min[0], s.window_max[0])),
                        float(np.clip(3 * sigma[2], s.window_min[1], s.window_max[1])))
        found = guesses(self._pose, self._last, self._step, apart_xy=s.hypothesis_xy, apart_theta=s.hypothesis_theta)
        best = search_guesses(self.map, sample, [(g, window) for g in found])
        result = refine(self.map, sample, np.array(best.pose))
        self.inliers = result.inliers
        if not result.ok or result.inliers < s.min_inliers:
            return False
        measured = np.linalg.inv(np.linalg.inv(result.information * s.information_scale + 1e-9 * np.eye(3))
                                 + np.diag([s.floor[0] ** 2, s.floor[0] ** 2, s.floor[1] ** 2]))
        predicted = np.linalg.inv(self._cov + 1e-12 * np.eye(3))
        cov = np.linalg.inv(predicted + measured)
        difference = result.pose - self._pose
        difference[2] = wrap(difference[2])
        correction = cov @ measured @ difference
        self._pose = compose(self._pose, (0.0, 0.0, 0.0)) + correction
        self._pose[2] = wrap(self._pose[2])
        self._cov = 0.5 * (cov + cov.T)
        self._step = relative(self._last, self._pose)
        self._last = self._pose.copy()
        return True
