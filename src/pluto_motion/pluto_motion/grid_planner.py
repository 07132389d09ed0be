"""The motionModule's planner over a map: shortest safe path on a :class:`PlanningGrid`, simplified
into waypoints.

Issue 12 ("Beyond Pluto": Pluto's ray following "can easily get trapped"): with a map, moveto plans
so that every reachable goal is reached, and an unreachable goal ends with a status, not a wander.

* Search: Dijkstra (``scipy.sparse.csgraph``) over the free cells, 8-connected (a diagonal step
  only where both cells beside it are free: no corner of the inflation is cut), from the goal; so
  one search serves every replan towards the same goal (:class:`Planner` keeps the last one).
* Cost: each step's length times ``1 + weight * ((comfort - c) / comfort)^2`` for a cell clearance
  ``c`` above the inflation that is within ``comfort`` of it: the path keeps away from walls where
  there is room and goes through the middle of doors.
* Simplification: from each waypoint, on along the path while a straight line from it reaches
  keeping the clearance the path itself had there, or :attr:`PlannerSettings.keep` if that is
  less (line of sight on the grid); so shortcuts never graze corners closer than the path did.

An unreachable goal (blocked, outside the grid, or not connected to the start) gives a
:class:`Plan` with ``reachable`` False and the reason.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from .planning_grid import PlanningGrid

__all__ = ['Plan', 'Planner', 'PlannerSettings']

#: The four neighbour directions that, with their opposites, make 8-connectivity.
_STEPS = ((0, 1), (1, 0), (1, 1), (1, -1))


@dataclasses.dataclass(frozen=True)
class PlannerSettings:
    """:param comfort: m above the inflation within which cells cost more.
    :param weight: how much more, at the inflation itself (the cost factor is 1 + weight there).
    :param keep: clearance (m, from the walls) a shortcut keeps where the path kept more.
    :param snap: m a start in a blocked cell may be moved to the nearest free one (a robot that
        the localization puts a little into the inflation still plans)."""

    comfort: float = 0.6
    weight: float = 1.5
    keep: float = 0.6
    snap: float = 0.3


@dataclasses.dataclass(frozen=True)
class Plan:
    """A planner's answer: ``waypoints`` (x, y) from the start (exclusive) to the goal
    (inclusive), their ``length`` (m, from the start), or ``reachable`` False and ``reason``."""

    reachable: bool
    waypoints: tuple[tuple[float, float], ...] = ()
    length: float = math.nan
    reason: str = ''
    #: The path's cells (iy, ix) before simplification, start first.
    cells: tuple[tuple[int, int], ...] = ()


class Planner:
    """Plans on one grid; :meth:`plan` re-uses the search of the last goal."""

    def __init__(self, grid: PlanningGrid, settings: PlannerSettings = PlannerSettings()) -> None:
        self.grid = grid
        self.settings = settings
        self._index = np.full(grid.shape, -1, dtype=np.int64)
        free = ~grid.blocked
        self._index[free] = np.arange(int(free.sum()))
        self._cells = np.argwhere(free)
        self._graph = self._build_graph()
        self._goal_cell: tuple[int, int] | None = None
        self._predecessors: NDArray | None = None

    def _cost(self) -> NDArray:
        s, g = self.settings, self.grid
        above = np.clip(g.clearance - g.settings.inflation, 0.0, s.comfort)
        return 1.0 + s.weight * ((s.comfort - above) / s.comfort) ** 2

    def _build_graph(self) -> object:
        g, cost, index = self.grid, self._cost(), self._index
        rows, cols, weights = [], [], []
        h, w = g.shape
        for dy, dx in _STEPS:
            rows_a, rows_b = slice(max(0, -dy), h - max(0, dy)), slice(max(0, dy), h - max(0, -dy))
            cols_a, cols_b = slice(max(0, -dx), w - max(0, dx)), slice(max(0, dx), w - max(0, -dx))
            a, b = index[rows_a, cols_a], index[rows_b, cols_b]
            ca, cb = cost[rows_a, cols_a], cost[rows_b, cols_b]
            both = (a >= 0) & (b >= 0)
            if dy and dx:       # no corner cutting: a diagonal step needs both cells beside it free
                both &= (index[rows_b, cols_a] >= 0) & (index[rows_a, cols_b] >= 0)
            rows.append(a[both])
            cols.append(b[both])
            weights.append(math.hypot(dy, dx) * g.resolution * 0.5 * (ca[both] + cb[both]))
        n = len(self._cells)
        return coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(n, n)).tocsr()

    def _start_cell(self, x: float, y: float) -> tuple[int, int] | None:
        """The start's cell, or the nearest free cell within :attr:`PlannerSettings.snap`."""
        g = self.grid
        c = g.cell(x, y)
        if c is None:
            return None
        if not g.blocked[c]:
            return c
        r = int(math.ceil(self.settings.snap / g.resolution))
        iy0, ix0 = max(0, c[0] - r), max(0, c[1] - r)
        window = ~g.blocked[iy0:c[0] + r + 1, ix0:c[1] + r + 1]
        if not window.any():
            return None
        iy, ix = np.nonzero(window)
        cx, cy = g.centre(iy + iy0, ix + ix0)
        d = np.hypot(cx - x, cy - y)
        k = int(np.argmin(d))
        return (int(iy[k] + iy0), int(ix[k] + ix0)) if d[k] <= self.settings.snap else None

    def plan(self, start: tuple[float, float], goal: tuple[float, float]) -> Plan:
        """The path from ``start`` to ``goal`` (metres, map frame)."""
        g = self.grid
        goal_cell = g.cell(*goal)
        if goal_cell is None:
            return Plan(False, reason=f'goal ({goal[0]:.2f}, {goal[1]:.2f}) is outside the map')
        if g.blocked[goal_cell]:
            return Plan(False, reason=f'goal ({goal[0]:.2f}, {goal[1]:.2f}) is too close to a wall '
                                      f'(clearance {g.clearance[goal_cell]:.2f} m < {g.settings.inflation:.2f} m) '
                                      'or outside the rectangle')
        start_cell = self._start_cell(*start)
        if start_cell is None:
            return Plan(False, reason=f'start ({start[0]:.2f}, {start[1]:.2f}) is in a wall or outside the map')
        if goal_cell != self._goal_cell:
            _, self._predecessors = dijkstra(self._graph, directed=False, indices=int(self._index[goal_cell]),
                                             return_predecessors=True)
            self._goal_cell = goal_cell
        assert self._predecessors is not None
        node = int(self._index[start_cell])
        goal_node = int(self._index[goal_cell])
        if node != goal_node and self._predecessors[node] < 0:
            return Plan(False, reason=f'goal ({goal[0]:.2f}, {goal[1]:.2f}) is not connected to the '
                                      f'start ({start[0]:.2f}, {start[1]:.2f})')
        path = [node]
        while node != goal_node:
            node = int(self._predecessors[node])
            path.append(node)
        cells = [(int(iy), int(ix)) for iy, ix in (self._cells[n] for n in path)]
        points = [(float(x), float(y)) for x, y in (g.centre(iy, ix) for iy, ix in cells)]
        points[-1] = (float(goal[0]), float(goal[1]))
        waypoints = self._simplify((float(start[0]), float(start[1])), points)
        length = sum(math.dist(a, b) for a, b in zip([start, *waypoints], waypoints))
        return Plan(True, tuple(waypoints), length, cells=tuple(cells))

    def _simplify(self, start: tuple[float, float], points: list[tuple[float, float]]) -> list[tuple[float, float]]:
        """Line of sight: from each waypoint, on along the path while the straight line keeps the
        clearance the path kept; the last point so reached is the next waypoint."""
        g = self.grid
        clear = np.array([g.clearance_at(*p) for p in points])
        floor = g.settings.inflation
        waypoints: list[tuple[float, float]] = []
        here, i = start, -1
        while i < len(points) - 1:
            best = i + 1
            lowest = np.inf
            for j in range(i + 1, len(points)):
                lowest = min(lowest, clear[j])
                need = max(floor, min(self.settings.keep, lowest) - g.resolution)
                if g.line_clearance(here, points[j]) < need:
                    break
                best = j
            waypoints.append(points[best])
            here, i = points[best], best
        return waypoints
