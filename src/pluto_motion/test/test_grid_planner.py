"""The motionModule's planner (pluto_motion.planning_grid, pluto_motion.grid_planner), pure: the grid's
inflation is exact at cell centres, off-limits regions are obstacles, paths never enter inflated
cells, stay within 1.3x of the shortest on open maps, go through the middle of the office's doors,
and a goal is unreachable exactly when it is not connected to the start."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from scipy import ndimage

from pluto_motion.grid_planner import Planner, PlannerSettings
from pluto_motion.planning_grid import GridSettings, build_grid, grid_from_map_file
from wurde_idl.segments import point_clearance

MAPS = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'
ROOM = [(0, 0, 10, 0), (10, 0, 10, 8), (10, 8, 0, 8), (0, 8, 0, 0)]
#: 8-connected grid paths are at most this much longer than the straight line (1 / cos 22.5 deg).
GRID_EXCESS = 1.0 / math.cos(math.pi / 8)


def _box(x: float, y: float, w: float, h: float) -> list[tuple[float, float, float, float]]:
    corners = [(x, y), (x + w, y), (x + w, y + h), (x, y + h)]
    return [(*a, *b) for a, b in zip(corners, corners[1:] + corners[:1])]


boxes = st.lists(st.tuples(st.floats(1.0, 8.0), st.floats(1.0, 6.0), st.floats(0.2, 1.5), st.floats(0.2, 1.5)),
                 max_size=4)
points = st.tuples(st.floats(0.5, 9.5), st.floats(0.5, 7.5))


def _clutter(obstacles: list) -> list:
    walls = list(ROOM)
    for x, y, w, h in obstacles:
        walls += _box(x, y, min(w, 9.9 - x), min(h, 7.9 - y))
    return walls


def _path(start: tuple[float, float], plan) -> list[tuple[float, float]]:
    return [start, *plan.waypoints]


def test_inflation_is_exact_at_cell_centres() -> None:
    walls = _clutter([(3.0, 2.0, 1.3, 0.7), (6.2, 4.1, 0.4, 2.0)])
    grid = build_grid(walls, [[(7.5, 0.5), (9.0, 0.5), (8.2, 2.0)]], (0, 0, 10, 8))
    iy, ix = np.indices(grid.shape)
    cx, cy = grid.centre(iy, ix)
    exact = point_clearance(np.column_stack([cx.ravel(), cy.ravel()]), grid.segments).reshape(grid.shape)
    outside_polygon = ~((cx > 7.6) & (cx < 8.9) & (cy > 0.6) & (cy < 1.8) & (grid.clearance == 0))
    assert np.array_equal(grid.blocked[outside_polygon], (exact < 0.39)[outside_polygon])
    assert grid.blocked[grid.cell(8.2, 1.0)]                      # inside the off-limits triangle
    assert grid.clearance[grid.cell(8.2, 1.0)] == 0.0
    assert not grid.blocked[grid.cell(5.0, 6.0)]


def test_bad_input_is_refused() -> None:
    with pytest.raises(ValueError, match='finite'):
        build_grid([(0, 0, math.nan, 1)], bounds=(0, 0, 2, 2))
    with pytest.raises(ValueError, match='bounds'):
        build_grid([])
    with pytest.raises(ValueError, match='no area'):
        build_grid([(0, 0, 1, 1)], bounds=(0, 0, 0, 2))
    with pytest.raises(ValueError, match='radius'):
        GridSettings(radius=-0.1)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(boxes, points, points)
@example([(2.0, 1.25, 1.0, 1.0)], (1.82, 0.9), (4.0, 1.0))   # a diagonal step cut the inflation's corner
def test_the_path_never_enters_inflated_cells(obstacles, start, goal) -> None:
    grid = build_grid(_clutter(obstacles), bounds=(0, 0, 10, 8))
    plan = Planner(grid).plan(start, goal)
    if not plan.reachable:
        return
    assert all(not grid.blocked[c] for c in plan.cells)
    if not grid.free_at(*start):                 # snapped out of the inflation: its first leg is short
        start = grid.centre(*plan.cells[0])
    for a, b in zip(_path(start, plan), plan.waypoints):
        assert grid.line_clearance(a, b) >= grid.settings.inflation
    assert plan.waypoints[-1] == pytest.approx(goal)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(1.0, 8.0), st.floats(1.0, 6.0), st.floats(0.2, 0.8), st.floats(0.2, 0.8)),
                max_size=3), points, points)
def test_paths_on_open_maps_are_within_1_3_of_the_shortest(obstacles, start, goal) -> None:
    grid = build_grid(_clutter(obstacles), bounds=(0, 0, 10, 8))
    if not (grid.free_at(*start) and grid.free_at(*goal)):
        return
    plan = Planner(grid).plan(start, goal)
    shortest = Planner(grid, PlannerSettings(weight=0.0)).plan(start, goal)
    assert plan.reachable == shortest.reachable
    if not plan.reachable:
        return
    # A lower bound of the shortest path: the unweighted grid path's length over the grid's excess.
    cells = [grid.centre(*c) for c in shortest.cells]
    grid_length = sum(math.dist(a, b) for a, b in zip(cells, cells[1:]))
    lower = max(math.dist(start, goal), grid_length / GRID_EXCESS - 2 * grid.resolution)
    assert plan.length <= 1.3 * lower + 2 * grid.resolution


@settings(max_examples=30, deadline=None)
@given(st.floats(0.3, 1.6), st.floats(1.5, 6.5), points, points)
def test_a_goal_is_unreachable_iff_the_gap_is_too_narrow(gap, at, start, goal) -> None:
    """A wall across the room at x = 5 with one gap; start west of it, goal east."""
    settings_ = GridSettings()
    needed = 2 * settings_.inflation
    if abs(gap - needed) < 0.1:                  # at the threshold, cell centres decide
        return
    walls = ROOM + [(5, 0, 5, at - gap / 2), (5, at + gap / 2, 5, 8)]
    grid = build_grid(walls, bounds=(0, 0, 10, 8), settings=settings_)
    start, goal = (min(start[0], 4.0), start[1]), (max(goal[0], 6.0), goal[1])
    if not (grid.free_at(*start) and grid.free_at(*goal)):
        return
    plan = Planner(grid).plan(start, goal)
    assert plan.reachable == (gap > needed), plan.reason
    if not plan.reachable:
        assert 'not connected' in plan.reason


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(0.5, 9.0), st.floats(0.5, 7.0), st.floats(0.3, 4.0), st.floats(0.3, 4.0)),
                min_size=2, max_size=6), points, points)
def test_unreachable_iff_disconnected_in_clutter(obstacles, start, goal) -> None:
    grid = build_grid(_clutter(obstacles), bounds=(0, 0, 10, 8))
    if not (grid.free_at(*start) and grid.free_at(*goal)):
        return
    labels, _ = ndimage.label(~grid.blocked, structure=np.ones((3, 3)))
    plan = Planner(grid).plan(start, goal)
    assert plan.reachable == (labels[grid.cell(*start)] == labels[grid.cell(*goal)])


def test_unreachable_goals_say_why() -> None:
    grid = grid_from_map_file(MAPS / 'office.xml')
    planner = Planner(grid)
    assert 'outside the map' in planner.plan((3, 7.5), (30, 3)).reason
    assert 'too close' in planner.plan((3, 7.5), (14.0, 3.5)).reason     # the lab's off-limits cell
    assert 'too close' in planner.plan((3, 7.5), (5.1, 3.0)).reason      # against a wall
    assert planner.plan((3, 7.5), (3, 3)).reachable


def test_office_corridor_to_room_goes_through_the_middle_of_the_door() -> None:
    grid = grid_from_map_file(MAPS / 'office.xml')
    plan = Planner(grid).plan((3.0, 7.5), (7.5, 3.0))       # corridor -> office2 (door x 7.05 .. 7.95)
    assert plan.reachable
    path = _path((3.0, 7.5), plan)
    crossing = [(a, b) for a, b in zip(path, path[1:]) if (a[1] - 6.3) * (b[1] - 6.3) <= 0]
    assert len(crossing) == 1
    (ax, ay), (bx, by) = crossing[0]
    x = ax + (6.3 - ay) * (bx - ax) / (by - ay) if by != ay else ax
    assert abs(x - 7.5) < 0.05                                 # the door's middle
    for a, b in zip(path, path[1:]):
        assert grid.line_clearance(a, b) >= 0.39
    assert plan.length < 1.3 * (math.dist((3.0, 7.5), (7.5, 6.3)) + math.dist((7.5, 6.3), (7.5, 3.0)))


def test_the_rectangle_restricts_the_plan() -> None:
    grid = build_grid(ROOM, bounds=(0, 0, 10, 8))
    inside = grid.restricted(lambda x, y: (x < 6.0))
    assert Planner(grid).plan((1, 1), (8, 6)).reachable
    assert not Planner(inside).plan((1, 1), (8, 6)).reachable
    assert Planner(inside).plan((1, 1), (5, 6)).reachable
