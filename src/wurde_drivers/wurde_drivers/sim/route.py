"""Random routes through a world for a robot of a given clearance: a roadmap and a coverage walk.

:class:`Roadmap` is a graph over the free space of a :class:`~.world.World`: its nodes are points
more than ``clearance`` from every wall and off-limits edge (outside the off-limits regions,
inside the bounds), its edges straight legs along which a disc of radius ``clearance`` touches
nothing.  Nodes come from a jittered lattice over the map and from the gaps between walls (the
middle of every door, and of every narrow passage a wall's end leaves), so that doors only a
little wider than the robot are found too.  Shortest paths are Dijkstra's (``heapq``: the venv
has no networkx).

:func:`random_route` walks that graph from the place ``start``: it goes, again and again, to a
node far from where the route has been (drawn with a seeded generator), straightening each stretch
with longer legs that are still clear, until the route is ``length_m`` long.  Every leg of the
result keeps ``clearance`` from every wall and off-limits region, so a robot of radius
:data:`ROBOT_RADIUS` driving it straight touches nothing, with :data:`MARGIN` to spare.
"""

from __future__ import annotations

import heapq
import math
import random
from collections import deque

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .clearance import legs_clear, point_segment_distance
from .world import World

__all__ = ['CLEARANCE', 'MARGIN', 'ROBOT_RADIUS', 'Roadmap', 'random_route', 'route_length']

#: The simulated Pluto's radius (``config/sim/sim-config.xml``, ``<base radius>``), metres.
ROBOT_RADIUS = 0.35
#: What a route keeps beyond the robot's radius, metres.
MARGIN = 0.05
#: The default clearance of a route: radius plus margin.
CLEARANCE = ROBOT_RADIUS + MARGIN

#: Checks are this much stricter than asked, so that World.first_contact agrees at the limit.
_EXACT = 1e-6
#: Nodes are rounded to millimetres (short waypoint text); the checks use the rounded points.
_DECIMALS = 3
#: Widest gap between walls whose middle becomes a node, metres.
_GAP = 3.5
#: Gaps up to this wide (metres; doors, the room beside furniture) also get nodes in front of
#: and behind their middle, on the line through it.
_NARROW = 2.0
#: Each node is tested against this many nearest nodes for an edge.
_NEIGHBOURS = 14
#: A node this close (metres) to the route so far counts as covered.
_COVERED = 2.0
#: The route picks its next goal among this many nearest uncovered nodes.
_CHOICES = 5
#: Shortcuts try to skip at most this many nodes of a path.
_SHORTCUT = 40


class Roadmap:
    """Free points of ``world`` and the clear legs between them.

    :param world: the map.
    :param clearance: metres every node and leg keeps from walls and off-limits regions.
    :param seed: seeds the jitter of the lattice.
    :param spacing: lattice step in metres; by default about 1500 lattice points over the map,
        between 0.5 and 1.5 m apart.
    """

    def __init__(self, world: World, clearance: float = CLEARANCE, *, seed: int = 0,
                 spacing: float | None = None) -> None:
        if not clearance >= 0.0:
            raise ValueError(f'clearance must not be negative, got {clearance}')
        self.world = world
        self.clearance = clearance
        box = world.bounds
        area = (box.xmax - box.xmin) * (box.ymax - box.ymin)
        self.spacing = spacing or min(1.5, max(0.5, math.sqrt(area / 1500.0)))
        self._obstacles = np.vstack([world.walls] + [
            np.hstack([polygon, np.roll(polygon, -1, axis=0)]) for polygon in world.offlimits])
        candidates = np.vstack([self._gap_points(), self._lattice(np.random.default_rng(seed))])
        self.nodes = _thin(candidates[self.free(candidates)], 0.25 * self.spacing)
        self._adjacent: list[dict[int, float]] = [{} for _ in range(len(self.nodes))]
        self._connect(np.arange(len(self.nodes)))

    # -- building --------------------------------------------------------------------------------

    def free(self, points: ArrayLike) -> NDArray:
        """``(N,)``: which points are inside the bounds, outside every off-limits region and more
        than the clearance from every wall and off-limits edge."""
        xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        box = self.world.bounds
        inside = ((xy[:, 0] >= box.xmin) & (xy[:, 0] <= box.xmax)
                  & (xy[:, 1] >= box.ymin) & (xy[:, 1] <= box.ymax))
        inside &= ~self.world.off_limits_mask(xy)
        keep = np.flatnonzero(inside)
        inside[keep] = self.legs_clear(xy[keep], xy[keep])
        return inside

    def _lattice(self, rng: np.random.Generator) -> NDArray:
        box, step = self.world.bounds, self.spacing
        xs = np.arange(box.xmin + step / 2, box.xmax, step)
        ys = np.arange(box.ymin + step / 2, box.ymax, step)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        return np.round(grid + rng.uniform(-0.3 * step, 0.3 * step, grid.shape), _DECIMALS)

    def _gap_points(self) -> NDArray:
        """Middles of the gaps a wall's end leaves to the walls around it (doors, passages), and
        for the narrow ones, points in front of and behind the middle."""
        walls = self._obstacles
        if len(walls) == 0:
            return np.empty((0, 2))
        ends = np.unique(np.vstack([walls[:, 0:2], walls[:, 2:4]]), axis=0)
        found = []
        for chunk in np.array_split(ends, max(1, len(ends) * len(walls) // (1 << 20))):
            a, b = walls[None, :, 0:2], walls[None, :, 2:4]
            edge = b - a
            t = np.clip(np.einsum('vwk,vwk->vw', chunk[:, None, :] - a, edge)
                        / np.einsum('vwk,vwk->vw', edge, edge), 0.0, 1.0)
            closest = a + t[..., None] * edge
            span = closest - chunk[:, None, :]
            width = np.hypot(span[..., 0], span[..., 1])
            v, w = np.nonzero((width > 2 * self.clearance) & (width <= _GAP))
            middle = chunk[v] + span[v, w] / 2
            found.append(middle)
            narrow = width[v, w] <= max(2.0 * self.spacing, _NARROW)
            across = span[v, w][narrow] / width[v, w][narrow, None]
            along = np.stack([-across[:, 1], across[:, 0]], axis=1)
            for offset in (-1.0, -0.5, 0.5, 1.0):
                found.append(middle[narrow] + offset * along)
        return np.round(np.vstack(found), _DECIMALS)

    def _connect(self, new: NDArray) -> None:
        """Test each node of ``new`` against its nearest nodes; keep the clear legs as edges."""
        count = min(_NEIGHBOURS, len(self.nodes) - 1)
        if count <= 0:
            return
        reach = max(3.0 * self.spacing, 2.5)
        cell = np.floor(self.nodes[new] / reach).astype(np.int64)
        found = [np.empty((0, 2), dtype=np.int64)]
        for chunk in np.array_split(new[np.lexsort((cell[:, 1], cell[:, 0]))],
                                    -(-len(new) // 256)):
            low = self.nodes[chunk].min(axis=0) - reach
            high = self.nodes[chunk].max(axis=0) + reach
            around = np.flatnonzero(np.all((self.nodes >= low) & (self.nodes <= high), axis=1))
            gaps = np.hypot(*(self.nodes[None, around, :]
                              - self.nodes[chunk, None, :]).transpose(2, 0, 1))
            gaps[chunk[:, None] == around[None, :]] = np.inf
            take = min(count, len(around) - 1)
            if take <= 0:
                continue
            nearest = np.argpartition(gaps, take - 1, axis=1)[:, :take]
            rows = np.repeat(np.arange(len(chunk)), take)
            near = gaps[rows, nearest.ravel()] <= reach
            pairs = np.stack([chunk[rows[near]], around[nearest.ravel()[near]]], axis=1)
            found.append(np.sort(pairs, axis=1))
        index = np.unique(np.vstack(found), axis=0)
        if len(index) == 0:
            return
        p, q = self.nodes[index[:, 0]], self.nodes[index[:, 1]]
        ok = self.legs_clear(p, q)
        for (i, j), length in zip(index[ok].tolist(), np.hypot(*(q - p)[ok].T).tolist()):
            self._adjacent[i][j] = self._adjacent[j][i] = length

    def legs_clear(self, p: ArrayLike, q: ArrayLike) -> NDArray:
        """``(L,)``: which legs ``p[i]``-``q[i]`` keep the clearance from every obstacle."""
        return legs_clear(p, q, self._obstacles, self.clearance + _EXACT)

    def neighbours(self, node: int) -> dict[int, float]:
        """The nodes one clear leg away from ``node`` -> the leg's length."""
        return dict(self._adjacent[node])

    def add(self, point: ArrayLike) -> int:
        """Add ``point`` as a node joined to its nearest nodes; its index (that of the node
        already there, if any).

        :raises ValueError: ``point`` is not free (too close to a wall, off limits, outside).
        """
        xy = np.asarray(point, dtype=np.float64).reshape(1, 2)
        if not self.free(xy)[0]:
            raise ValueError(f'{tuple(xy[0])} is not free with clearance {self.clearance} m')
        same = np.flatnonzero(np.all(self.nodes == xy, axis=1))
        if len(same):
            return int(same[0])
        self.nodes = np.vstack([self.nodes, xy])
        self._adjacent.append({})
        self._connect(np.array([len(self.nodes) - 1]))
        return len(self.nodes) - 1

    # -- searching -------------------------------------------------------------------------------

    def reachable(self, node: int) -> NDArray:
        """Indices of the nodes connected to ``node`` (itself included), sorted."""
        seen = {node}
        todo = deque([node])
        while todo:
            for other in self._adjacent[todo.popleft()]:
                if other not in seen:
                    seen.add(other)
                    todo.append(other)
        return np.array(sorted(seen))

    def shortest(self, node: int, *, goals: NDArray | None = None,
                 enough: int = 0) -> tuple[NDArray, NDArray, list[int]]:
        """Dijkstra from ``node``: ``(distance, predecessor, settled)``.

        ``settled`` lists the nodes whose distance is final, nearest first; the search stops
        early once ``enough`` nodes with ``goals[node]`` true are settled.  Unreached nodes have
        distance ``inf`` and predecessor -1.
        """
        distance = np.full(len(self.nodes), np.inf)
        before = np.full(len(self.nodes), -1)
        distance[node] = 0.0
        heap = [(0.0, node)]
        settled: list[int] = []
        done = set()
        found = 0
        while heap:
            d, here = heapq.heappop(heap)
            if here in done:
                continue
            done.add(here)
            settled.append(here)
            if goals is not None and goals[here]:
                found += 1
                if found >= enough > 0:
                    break
            for other, length in self._adjacent[here].items():
                if d + length < distance[other]:
                    distance[other] = d + length
                    before[other] = here
                    heapq.heappush(heap, (d + length, other))
        return distance, before, settled

    def straightened(self, path: list[int]) -> list[int]:
        """``path`` with nodes skipped wherever a longer leg is still clear."""
        result = [path[0]]
        i = 0
        while i < len(path) - 1:
            ahead = np.array(path[i + 2:i + 2 + _SHORTCUT], dtype=int)
            best = i + 1
            if len(ahead):
                ok = self.legs_clear(np.repeat(self.nodes[path[i]][None], len(ahead), axis=0),
                                     self.nodes[ahead])
                if ok.any():
                    best = i + 2 + int(np.flatnonzero(ok)[-1])
            result.append(path[best])
            i = best
        return result


def _thin(points: NDArray, cell: float) -> NDArray:
    """``points`` with at most one (the first) in each square of side ``cell``."""
    if len(points) == 0:
        return points.reshape(0, 2)
    keys = np.floor(points / cell).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    return points[np.sort(first)]


def route_length(route: list[tuple[float, float]]) -> float:
    """The length in metres of the polyline through ``route``."""
    return sum(math.dist(a, b) for a, b in zip(route, route[1:]))


def random_route(world: World, seed: int, length_m: float, *,
                 clearance: float = CLEARANCE, home: bool = False) -> list[tuple[float, float]]:
    """Waypoints from the place ``start`` through the world, at least ``length_m`` long.

    The first waypoint is ``start`` itself; each straight leg keeps more than ``clearance`` from
    every wall and off-limits region.  The route heads, again and again, for a part of the map it
    has not been near yet, so a long enough route covers the free space connected to ``start``.
    With ``home`` the route then comes back to ``start`` by the shortest way (a loop, for SLAM's
    loop closure); ``length_m`` counts the way out only.

    :raises KeyError: the world has no place ``start``.
    :raises ValueError: ``start`` is not free with that clearance, or nothing around it is.
    """
    rng = random.Random(seed)
    start = world.place('start')
    roadmap = Roadmap(world, clearance, seed=seed)
    here = roadmap.add((start.x, start.y))
    route = [(start.x, start.y)]
    if length_m <= 0:
        return route
    if not roadmap.neighbours(here):
        raise ValueError(f'no clear leg leaves start {tuple(start)[:2]} with clearance '
                         f'{clearance} m')
    away = np.full(len(roadmap.nodes), np.inf)   # how far each node is from the route so far
    _visit(roadmap, away, route[0], route[0])
    total = 0.0
    first = last = here
    while total < length_m:
        fresh = away > _COVERED
        distance, before, settled = roadmap.shortest(here, goals=fresh, enough=_CHOICES)
        choices = [node for node in settled if fresh[node]]
        if not choices:  # all covered: wander to any node a fair way off
            far = distance[settled].max()
            choices = [node for node in settled if distance[node] >= 0.5 * far]
        target = rng.choice(choices)
        path = [target]
        while path[-1] != here:
            path.append(int(before[path[-1]]))
        for node in roadmap.straightened(path[::-1])[1:]:
            point = tuple(roadmap.nodes[node].tolist())
            if point == route[-1]:
                continue
            total += math.dist(route[-1], point)
            _visit(roadmap, away, route[-1], point)
            route.append(point)
            last = node
            if total >= length_m:
                break
        here = target
    if home and last != first:
        _, before, _ = roadmap.shortest(last)
        path = [first]
        while path[-1] != last:
            path.append(int(before[path[-1]]))
        route.extend(tuple(roadmap.nodes[node].tolist()) for node in roadmap.straightened(path[::-1])[1:])
    return route


def _visit(roadmap: Roadmap, away: NDArray, a: tuple[float, float],
           b: tuple[float, float]) -> None:
    """Lower ``away`` to each node's distance from the leg ``a``-``b``."""
    gap = point_segment_distance(roadmap.nodes, np.asarray(a)[None], np.asarray(b)[None])
    np.minimum(away, gap, out=away)
