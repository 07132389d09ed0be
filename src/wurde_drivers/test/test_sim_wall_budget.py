"""The clearance budget (:mod:`wurde_drivers.sim.wall_budget`) answers exactly what the full tests do:
a disc walked at random through a room with walls inside it, close to them and into them, gets
from :meth:`World.first_contact` the sweep of every wall, and from :meth:`World.wall_within` the
nearest wall's answer, at every step, whatever the budget knew from the steps before."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.sim.raycast import Segments
from wurde_drivers.sim.world import World

#: A 6 m x 4 m room with a pillar and a half wall: open space, corners and narrow passages.
WALLS = [(0, 0, 6, 0), (6, 0, 6, 4), (6, 4, 0, 4), (0, 4, 0, 0),
         (2, 1.5, 2.5, 1.5), (2.5, 1.5, 2.5, 2), (2.5, 2, 2, 2), (2, 2, 2, 1.5),
         (4, 0, 4, 2.2)]
RADIUS = 0.35
REACH = 0.36

moves = st.lists(st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3)), min_size=1, max_size=60)


@settings(max_examples=150, deadline=None)
@given(start=st.tuples(st.floats(0.2, 5.8), st.floats(0.2, 3.8)), steps=moves)
def test_the_budget_answers_as_the_full_tests(start: tuple[float, float], steps: list[tuple[float, float]]) -> None:
    world = World(WALLS)
    reference = Segments(np.array(WALLS, dtype=np.float64))
    x, y = start
    for dx, dy in steps:
        end = (x + dx, y + dy)
        free = world.first_contact((x, y), end, RADIUS)
        assert free == reference.sweep_circle((x, y), end, RADIUS), ((x, y), end)
        x, y = x + free * dx, y + free * dy
        wall = world.wall_within((x, y), REACH)
        distance, closest, _ = reference.nearest((x, y))
        if distance <= REACH:
            assert wall is not None and np.array_equal(wall, closest)
        else:
            assert wall is None


def test_open_space_is_answered_without_the_walls() -> None:
    """Steps of 1 cm in the open are answered from the first step's lookup: the walls are
    consulted again only when the budget runs out."""
    world = World(WALLS)
    looked: list[tuple[float, float]] = []
    lookup = world._walls_budget.nearest

    def counted(point):
        looked.append((float(point[0]), float(point[1])))
        return lookup(point)

    world._walls_budget.nearest = counted
    x = 0.6
    while x < 1.6:
        assert world.first_contact((x, 1.0), (x + 0.01, 1.0), RADIUS) == 1.0
        assert world.wall_within((x + 0.01, 1.0), REACH) is None
        x += 0.01
    # From (0.6, 1) the nearest wall is 0.6 m away: the budget lasts 0.6 - 0.35 m of the way,
    # then a lookup from further on lasts again.  100 steps, a handful of lookups.
    assert 1 <= len(looked) <= 6, looked
    assert math.isclose(looked[0][0], 0.6)
