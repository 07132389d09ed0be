"""The slamModule's two methods (``-e``), behind one interface.

- :class:`LineSlam` (``lines``, the default; Pluto 7.2's "compressed Kalman Filter"): line
  landmarks in a compressed EKF (:class:`.slam_filter.SlamFilter`); the map is its walls.  For
  buildings of long straight walls, as the simulator's maps are.
- :class:`ScanSlam` (``scans``): scan-matching graph SLAM with loop closure
  (:class:`.graph_slam.GraphSlam`); the map is an occupancy grid of every scan at its optimized
  pose, and the walls are the grid's outlines (:func:`.occupancy.grid_walls`).  For real robots'
  data: clutter, glass, people and loops of hundreds of metres.

Both are :class:`.estimation.Method` s and give :meth:`map_data` (the suite's map: walls and the
place ``start``) and :meth:`grid` (an occupancy grid, or None); ``status`` is the slamModule's
status data triple's first two numbers.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from wurde_idl.mapfile import MapData, Place

from .estimation import Method, Scan
from .geometry import compose, inverse
from .graph_slam import GraphSlam, GraphSlamSettings
from .occupancy import Grid, build_grid, grid_walls
from .slam_filter import LINE_EXTRACTION, SlamFilter

__all__ = ['LineSlam', 'METHODS', 'ScanSlam', 'SlamMethod']

#: Scans between two counts of a line map's confirmed walls (walls() resolves every extent).
WALL_COUNT_EVERY = 10


class SlamMethod(Method, Protocol):
    def map_data(self, name: str, *, mount: ArrayLike = (0.0, 0.0, 0.0)) -> MapData: ...
    def grid(self) -> Grid | None: ...
    def status(self) -> tuple[float, float]: ...


class LineSlam:
    """Pluto's line-feature SLAM.  ``status``: confirmed walls, landmarks."""

    def __init__(self) -> None:
        self.filter = SlamFilter()
        self.updates = 0
        self.walls = 0
        self.landmarks = 0

    @property
    def pose(self) -> NDArray:
        return self.filter.pose

    @property
    def covariance(self) -> NDArray:
        return np.asarray(self.filter.covariance)[:3, :3]

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        self.filter.set_pose(pose, covariance)

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        self.filter.predict(increment, increment_covariance)

    def update(self, scan: Scan) -> bool:
        result = self.filter.update(scan.lines(**LINE_EXTRACTION))
        if self.updates % WALL_COUNT_EVERY == 0:
            self.walls = len(self.filter.walls())
        self.updates += 1
        self.landmarks = result.landmarks
        return result.matched > 0

    def status(self) -> tuple[float, float]:
        return float(self.walls), float(len(self.filter))

    def map_data(self, name: str, *, mount: ArrayLike = (0.0, 0.0, 0.0)) -> MapData:
        data = self.filter.to_map_data(name, mount=mount)
        self.walls = len(data.walls)
        return data

    def grid(self) -> Grid | None:
        return None


class ScanSlam:
    """Scan-matching graph SLAM.  ``status``: walls of the last map made, nodes of the graph."""

    def __init__(self, settings: GraphSlamSettings = GraphSlamSettings(), *, resolution: float = 0.05) -> None:
        self.slam = GraphSlam(settings)
        self.resolution = resolution
        self.walls = 0
        self._grid: tuple[tuple[int, int, int], Grid] | None = None

    @property
    def pose(self) -> NDArray:
        return self.slam.pose

    @property
    def covariance(self) -> NDArray:
        return self.slam.covariance

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        self.slam.set_pose(pose, covariance)
        self._grid = None

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        self.slam.predict(increment, increment_covariance)

    def update(self, scan: Scan) -> bool:
        return self.slam.update_ranges(scan.ranges, scan.angles, max_range=scan.max_range).matched

    def status(self) -> tuple[float, float]:
        return float(self.walls), float(len(self.slam))

    def trajectory(self) -> NDArray:
        """Every scan's laser pose in the final map (the graph solved once more first)."""
        self.slam.finish()
        return self.slam.trajectory()

    def grid(self) -> Grid | None:
        """The occupancy grid of every node's scan at its pose now (made again when the graph
        has changed since)."""
        if not len(self.slam):
            return None
        version = (len(self.slam), self.slam.closures, self.slam.solves)
        if self._grid is None or self._grid[0] != version:
            rays = [(node.angles, node.ranges) for node in self.slam.nodes]
            grid = build_grid(self.slam.graph.poses, rays, resolution=self.resolution,
                              max_range=self.slam.settings.max_range)
            self._grid = (version, grid)
        return self._grid[1]

    def map_data(self, name: str, *, mount: ArrayLike = (0.0, 0.0, 0.0)) -> MapData:
        grid = self.grid()
        walls = grid_walls(grid) if grid is not None else np.zeros((0, 4))
        self.walls = len(walls)
        robot = compose(self.slam.origin, inverse(mount))
        return MapData(name, walls=tuple(map(tuple, walls.tolist())),
                       places={'start': Place(*(float(v) for v in robot))})


#: The methods by their ``-e`` name.
METHODS = {'lines': LineSlam, 'scans': ScanSlam}
