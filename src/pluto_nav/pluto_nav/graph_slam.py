"""Scan-matching graph SLAM: the slamModule's estimator for real laser data.

The line-feature EKF (:mod:`.slam_filter`, Pluto's own) maps rooms made of straight walls; real
buildings have clutter, glass, people and doors, where lines are few and unreliable.  This
estimator uses every laser point instead:

1. **Front end** (each scan): the scan is matched against the last ``local_nodes`` nodes' points:
   a correlative search (:mod:`.correlative`) round the odometry's guess — and round the last
   matched motion and standing still, since real odometry lags and jumps — then point-to-line ICP
   (:mod:`.icp`).  A scan that moved ``node_distance`` or turned ``node_turn`` from the last node
   becomes a node, tied to the previous one by the match (its information from ICP, so a
   corridor's match holds across the corridor, not along it); other scans are placed relative to
   the last node.
2. **Loop closure** (every ``loop_every`` nodes): within ``loop_radius`` of a node left
   ``loop_separation`` metres of path ago, the scan is searched for over a wide window, coarse
   then fine, and refined by ICP; the closure is kept only if most of the scan fits, no distant
   pose fits nearly as well (a look-alike corridor) and the match pins the position in every
   direction.
3. **Back end**: the pose graph (:mod:`.pose_graph`) is solved after each closure, with a robust
   kernel on closures so that a wrong one bends the map a little instead of folding it.

Its interface is the estimators' (:class:`.estimator.Estimator`); :meth:`GraphSlam.trajectory`
and :meth:`GraphSlam.map_points` give the whole trajectory and the map's points after it.
Deterministic: the same scans give the same poses.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .correlative import Window, guesses, search, search_guesses
from .geometry import compose, relative, transform_points
from .graph_slam_settings import GraphSlamSettings, GraphSlamUpdate
from .icp import IcpResult, refine
from .lines import scan_points
from .point_map import PointMap, voxel_filter
from .pose_graph import Edge, PoseGraph

__all__ = ['GraphSlam', 'GraphSlamSettings', 'GraphSlamUpdate', 'NodeScan']

#: m and rad apart: two window poses this close are one peak, for the ambiguity test.
PEAK_XY, PEAK_THETA = 0.5, math.radians(10.0)
#: Fewest points a scan needs to be matched.
MIN_POINTS = 20


@dataclasses.dataclass(frozen=True)
class NodeScan:
    """What a node keeps of its scan: its thinned points and its rays, in the node's (laser) frame."""

    points: NDArray          # (N, 2), thinned to the map's voxel
    angles: NDArray          # every beam's direction
    ranges: NDArray          # every beam's range, inf for "nothing within range", NaN no reading


def _floored(information: NDArray, scale: float, floor: tuple[float, float]) -> NDArray:
    """``information * scale`` with ``floor`` (m, rad) standard deviations added to its covariance."""
    covariance = np.linalg.inv(information * scale + 1e-9 * np.eye(3))
    covariance = covariance + np.diag([floor[0] ** 2, floor[0] ** 2, floor[1] ** 2])
    return np.linalg.inv(covariance)


def _rotate_information(information: NDArray, theta: float) -> NDArray:
    """An x-y-theta information given in the map's axes, in the axes of a frame at ``theta``."""
    c, s = math.cos(theta), math.sin(theta)
    rotation = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    return rotation @ information @ rotation.T


class GraphSlam:
    """The estimator (see the module's description).  Poses are the laser's."""

    def __init__(self, settings: GraphSlamSettings = GraphSlamSettings()) -> None:
        self.settings = settings
        self._reset()

    def _reset(self) -> None:
        self.graph = PoseGraph()
        self.nodes: list[NodeScan] = []
        self.path: list[float] = []              # metres driven up to each node
        self.attached: list[tuple[int, NDArray]] = []   # every scan: (node, pose in the node's frame)
        self.closures = 0
        self.solves = 0
        self.origin = np.zeros(3)
        self.origin_covariance = np.zeros((3, 3))
        self._pose = np.zeros(3)
        self._pending = np.zeros(3)              # odometry since the last scan
        self._step = np.zeros(3)                 # the last matched motion between scans
        self._information = np.eye(3) * 1e4
        self._local: PointMap | None = None
        self._local_built = -1
        self._loop_cache: tuple[int, int, PointMap] | None = None
        self._version = 0

    # -- the estimator's interface -------------------------------------------------------------
    @property
    def pose(self) -> NDArray:
        return self._pose.copy()

    @property
    def covariance(self) -> NDArray:
        """Of the last scan's match against the local map (the map's own frame is exact)."""
        return np.linalg.inv(self._information)

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike | None = None) -> None:
        """Start a new map whose frame puts the first scan at ``pose``."""
        self._reset()
        self.origin = np.asarray(pose, dtype=np.float64).reshape(3).copy()
        if covariance is not None:
            self.origin_covariance = np.asarray(covariance, dtype=np.float64)
        self._pose = self.origin.copy()

    def predict(self, increment: ArrayLike, covariance: ArrayLike | None = None) -> None:
        """The laser's odometry increment since the last scan (its covariance is not needed: the
        search window grows with the increment itself)."""
        self._pending = compose(self._pending, np.asarray(increment, dtype=np.float64))

    def update_ranges(self, ranges: ArrayLike, angles: ArrayLike, *, max_range: float = math.inf
                      ) -> GraphSlamUpdate:
        """One scan: ``ranges`` (m; inf for nothing within range) at ``angles`` in the laser's frame."""
        s = self.settings
        r = np.asarray(ranges, dtype=np.float64)
        phi = np.asarray(angles, dtype=np.float64)
        limit = min(s.max_range, max_range)
        _, _, x, y, _ = scan_points(r, angles=phi, min_range=s.min_range, max_range=limit)
        points = np.column_stack([x, y])
        return self._update(points, NodeScan(voxel_filter(points, s.map_voxel), phi.copy(),
                                             np.where(r >= max_range, np.inf, r)))

    # -- per scan ------------------------------------------------------------------------------
    def _update(self, points: NDArray, scan: NodeScan) -> GraphSlamUpdate:
        s = self.settings
        increment, self._pending = self._pending, np.zeros(3)
        if not self.nodes:
            self._add_node(self._pose, scan, None)
            return GraphSlamUpdate(True, 1.0, True, 0, 1, 0)
        guess = compose(self._pose, increment)
        sample = voxel_filter(points, s.scan_voxel)
        result = self._match_local(sample, guess, increment) if len(sample) >= MIN_POINTS else None
        good = result if result is not None and result.ok else None
        matched = good is not None
        pose = good.pose if good is not None else guess
        if good is not None:
            self._information = _floored(good.information, s.information_scale, s.step_floor)
        self._step = relative(self._pose, pose)
        self._pose = pose
        last = len(self.nodes) - 1
        from_node = relative(self.graph.poses[last], pose)
        loops = 0
        is_node = (math.hypot(from_node[0], from_node[1]) >= s.node_distance
                   or abs(from_node[2]) >= s.node_turn)
        if is_node:
            information = (_rotate_information(self._information, float(self.graph.poses[last][2]))
                           if matched else np.diag([1.0 / 0.1 ** 2, 1.0 / 0.1 ** 2, 1.0 / math.radians(5) ** 2]))
            self._add_node(pose, scan, Edge(last, len(self.nodes), tuple(from_node), information, kind='step'))
            if len(self.nodes) % s.loop_every == 0 and len(sample) >= MIN_POINTS:
                loops = self._close_loop(sample)
        else:
            self.attached.append((last, from_node))
        inliers = result.inliers if result is not None else 0.0
        return GraphSlamUpdate(matched, inliers, is_node, loops, len(self.nodes), self.closures)

    def _add_node(self, pose: NDArray, scan: NodeScan, edge: Edge | None) -> None:
        index = self.graph.add_node(pose)
        self.nodes.append(scan)
        if edge is None:
            self.path.append(0.0)
        else:
            self.path.append(self.path[-1] + math.hypot(edge.z[0], edge.z[1]))
            self.graph.add_edge(edge)
        self.attached.append((index, np.zeros(3)))

    def _local_map(self) -> PointMap | None:
        s = self.settings
        count = len(self.nodes)
        if self._local is None or count - self._local_built >= s.local_rebuild:
            first = max(0, count - s.local_nodes)
            points = [transform_points(self.graph.poses[i], self.nodes[i].points) for i in range(first, count)]
            merged = voxel_filter(np.vstack(points), s.map_voxel)
            self._local = (PointMap(merged, resolution=s.field_resolution, sigma=s.field_sigma)
                           if len(merged) >= MIN_POINTS else None)
            self._local_built = count
        return self._local

    def _match_local(self, sample: NDArray, guess: NDArray, increment: NDArray) -> IcpResult | None:
        s = self.settings
        local = self._local_map()
        if local is None:
            return None
        window = Window(s.window_xy + s.window_growth * math.hypot(increment[0], increment[1]),
                        s.window_theta + s.window_growth * abs(increment[2]))
        others = Window(s.window_xy, s.window_theta)
        found = guesses(guess, self._pose, self._step, apart_xy=s.hypothesis_xy, apart_theta=s.hypothesis_theta)
        best = search_guesses(local, sample, [(g, window if k == 0 else others) for k, g in enumerate(found)])
        return refine(local, sample, np.array(best.pose))

    # -- loop closure ----------------------------------------------------------------------------
    def _close_loop(self, sample: NDArray) -> int:
        s = self.settings
        k = len(self.nodes) - 1
        poses, path = self.graph.poses, np.asarray(self.path)
        far = path[k] - path[:k] > s.loop_separation
        distance = np.hypot(poses[:k, 0] - poses[k, 0], poses[:k, 1] - poses[k, 1])
        near = far & (distance < s.loop_radius)
        if not near.any():
            return 0
        j = int(np.flatnonzero(near)[np.argmin(distance[near])])
        submap = self._loop_map(j, far)
        if submap is None:
            return 0
        guess = relative(poses[j], poses[k])
        coarse = Window(s.loop_window_xy, s.loop_window_theta, math.radians(1.0), s.loop_coarse)
        found = search(submap, sample, guess, coarse)
        best = found[0]
        rival = next((c for c in found[1:] if c.distance(best)[0] > PEAK_XY or c.distance(best)[1] > PEAK_THETA), None)
        if rival is not None and rival.score > s.loop_ambiguity * best.score:
            return 0
        step = submap.resolution * s.loop_coarse
        fine = search(submap, sample, np.array(best.pose), Window(step, math.radians(1.5), math.radians(0.5)))[0]
        result = refine(submap, sample, np.array(fine.pose))
        if not result.ok or result.inliers < s.loop_min_inliers:
            return 0
        if np.linalg.eigvalsh(result.information[:2, :2])[0] < s.loop_min_information:
            return 0
        edge = Edge(j, k, tuple(result.pose), _floored(result.information, s.information_scale, s.loop_floor),
                    s.loop_robust, 'loop')
        return self._accept([edge])

    def _accept(self, edges: list[Edge]) -> int:
        for edge in edges:
            self.graph.add_edge(edge)
        self.closures += len(edges)
        self._solve()
        return len(edges)

    def _loop_map(self, j: int, far: NDArray) -> PointMap | None:
        """The map round node ``j`` (the nodes within ``loop_nodes`` of it that are ``far``), in
        ``j``'s frame; kept while the graph is unchanged."""
        s = self.settings
        if self._loop_cache is not None and self._loop_cache[:2] == (j, self._version):
            return self._loop_cache[2]
        poses = self.graph.poses
        members = [i for i in range(max(0, j - s.loop_nodes), min(len(far), j + s.loop_nodes + 1)) if far[i]]
        points = [transform_points(relative(poses[j], poses[i]), self.nodes[i].points) for i in members]
        merged = voxel_filter(np.vstack(points), s.map_voxel) if points else np.zeros((0, 2))
        submap = (PointMap(merged, resolution=s.field_resolution, sigma=s.field_sigma)
                  if len(merged) >= MIN_POINTS else None)
        self._loop_cache = (j, self._version, submap)  # type: ignore[assignment]
        return submap

    def _solve(self) -> None:
        last_node, last_pose = self.attached[-1]
        self.graph.optimize()
        self.solves += 1
        self._version += 1
        self._local = None
        self._pose = compose(self.graph.poses[last_node], last_pose)

    # -- results ---------------------------------------------------------------------------------
    def finish(self) -> None:
        """A last solution of the graph (closures since the last one are already in)."""
        if self.graph.edges:
            self._solve()

    def trajectory(self) -> NDArray:
        """``(scans, 3)``: every scan's laser pose, in the order they came."""
        poses = self.graph.poses
        return np.array([compose(poses[node], rel) for node, rel in self.attached]).reshape(-1, 3)

    def map_points(self) -> NDArray:
        """Every node's points in the map's frame, thinned to the map's voxel."""
        if not self.nodes:
            return np.zeros((0, 2))
        points = [transform_points(self.graph.poses[i], node.points) for i, node in enumerate(self.nodes)]
        return voxel_filter(np.vstack(points), self.settings.map_voxel)

    def __len__(self) -> int:
        return len(self.nodes)
