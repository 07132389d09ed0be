"""Tunables and per-scan results of the scan-matching graph SLAM (:class:`.graph_slam.GraphSlam`).

The defaults were chosen on the two public benchmark logs in the project's shared data (Freiburg
079 and MIT CSAIL, SICK lasers at 0.5 degrees) and checked with their odometry degraded and their
scans thinned, so that they hold for other real logs of the kind, not for one.
"""

from __future__ import annotations

import dataclasses
import math

__all__ = ['GraphSlamSettings', 'GraphSlamUpdate']


@dataclasses.dataclass(frozen=True)
class GraphSlamSettings:
    """Tunables of :class:`.graph_slam.GraphSlam` (defaults in brackets)."""

    #: m: readings beyond this are not used [30]; far walls keep the pose along a corridor but a
    #: SICK's far readings are sparse and noisy.
    max_range: float = 30.0
    #: m: readings nearer than this are the robot itself or dirt on the window [0.1].
    min_range: float = 0.1
    #: m: a scan's points are thinned to one per cell of this size before matching [0.1].
    scan_voxel: float = 0.1
    #: m: the maps' points are thinned to one per cell of this size [0.05].
    map_voxel: float = 0.05
    #: A new node when the robot has moved this far (m) or turned this much (rad) since the last
    #: node [0.1, 3 deg]; scans in between are matched too, and placed relative to the last node.
    node_distance: float = 0.1
    node_turn: float = math.radians(3.0)
    #: The local map the next scan is matched against: the last this many nodes [20] ...
    local_nodes: int = 20
    #: ... rebuilt after this many new nodes [2].
    local_rebuild: int = 2
    #: m per cell of the likelihood fields [0.1] and their spread (m) [0.1]: the correlative
    #: search only has to bring the scan within ICP's reach, and a coarser field is four times
    #: cheaper to build (with 0.05 m the benchmark logs scored the same).
    field_resolution: float = 0.1
    field_sigma: float = 0.1
    #: The scan-to-map search round the odometry's guess: half-widths (m, rad) [0.3, 6 deg], grown
    #: by this fraction of the odometry increment's length and turn [0.2]: a long or fast step's
    #: odometry is the less certain.
    window_xy: float = 0.3
    window_theta: float = math.radians(6.0)
    window_growth: float = 0.2
    #: Guesses beside the odometry's when they differ from it by this much (m, rad) [0.1, 5 deg]:
    #: the last matched motion again (odometry that lags, then catches up in one jump, as old
    #: CARMEN logs' laser lines have it) and standing still.
    hypothesis_xy: float = 0.1
    hypothesis_theta: float = math.radians(5.0)
    #: Factor on ICP's information (neighbouring beams are not independent) [1/10].
    information_scale: float = 0.1
    #: Standard deviations added to every match's covariance: (m, rad) for consecutive scans
    #: [0.005, 0.2 deg], for loop closures [0.01, 0.3 deg].
    step_floor: tuple[float, float] = (0.005, math.radians(0.2))
    loop_floor: tuple[float, float] = (0.01, math.radians(0.3))
    #: Loop closures: tried every this many nodes [2] ...
    loop_every: int = 2
    #: ... with the nearest node at most this far (m) by the current estimate [3] that the robot
    #: left at least this many metres of path ago [8] ...
    loop_radius: float = 3.0
    loop_separation: float = 8.0
    #: ... matched against the map of this many nodes either side of it [15] ...
    loop_nodes: int = 15
    #: ... in a window of these half-widths (m, rad) [1, 15 deg], searched at this many field
    #: cells per step first [2] (on both benchmark logs the front end had drifted at most 0.13 m
    #: and 2.6 deg when a loop closed, after up to 94 m without a closure: the window holds
    #: loops many times longer; a wider one only lets look-alike places in) ...
    loop_window_xy: float = 1.0
    loop_window_theta: float = math.radians(15.0)
    loop_coarse: int = 2
    #: ... and taken when this fraction of the scan's points fits the map [0.7], no pose of the
    #: window that is not near the best scores this fraction of its score [0.9], and the match
    #: holds the position in every direction (least eigenvalue of its x-y information, 1/m^2) [1000].
    loop_min_inliers: float = 0.7
    loop_ambiguity: float = 0.9
    loop_min_information: float = 1000.0
    #: Loop closures' robust kernel: Huber beyond this many standard deviations [3].
    loop_robust: float = 3.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.min_range < self.max_range:
            raise ValueError('need 0 <= min_range < max_range')
        if self.local_nodes < 1 or self.local_rebuild < 1 or self.loop_every < 1 or self.loop_nodes < 0:
            raise ValueError('local_nodes, local_rebuild and loop_every must be 1 or more, loop_nodes 0 or more')
        if min(self.scan_voxel, self.map_voxel, self.field_resolution, self.field_sigma) <= 0.0:
            raise ValueError('voxels, field resolution and sigma must be positive')


@dataclasses.dataclass(frozen=True)
class GraphSlamUpdate:
    """What one :meth:`.graph_slam.GraphSlam.update` did.

    :ivar matched: the scan was matched to the map (False: too few points; odometry alone).
    :ivar inliers: fraction of the scan's points that fit the local map.
    :ivar node: whether the scan became a node of the graph.
    :ivar loops: loop closures added with this scan.
    :ivar nodes: nodes in the graph; ``closures`` loop closures in all.
    """

    matched: bool
    inliers: float
    node: bool
    loops: int
    nodes: int
    closures: int
