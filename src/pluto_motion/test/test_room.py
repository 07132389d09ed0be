"""The room round a place (pluto_motion.room), which the mission explores: on the shipped office
and on generated rooms with a door gap in any wall beside a corridor, the bounds are the room's
walls to a cell — the gap never lets the room run on — and explore's rectangle lies inside them."""

from __future__ import annotations

import math
import pathlib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from wurde_idl.mapfile import load_map_data

from pluto_motion.motion_command import Rectangle
from pluto_motion.planning_grid import build_grid, grid_from_map_file
from pluto_motion.room import explore_area, room_bounds

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'
DOOR = 0.9


def test_the_office_rooms() -> None:
    world = load_map_data(OFFICE)
    grid = grid_from_map_file(OFFICE)
    cell = grid.resolution * 1.5
    office2 = world.places['office2']
    assert room_bounds(grid, office2.x, office2.y) == pytest.approx((5.0, 10.0, 0.0, 6.3), abs=cell)
    lab = world.places['lab']       # the bench and the off-limits work cell bound the lab's free space
    assert room_bounds(grid, lab.x, lab.y) == pytest.approx((10.0, 13.2, 1.8, 6.3), abs=cell)
    area = explore_area(grid, office2.x, office2.y, 0.6)
    assert (area.x, area.y, area.theta) == pytest.approx((5.6, 3.15, 0.0), abs=cell)  # west side, facing east
    assert (area.b, area.h) == pytest.approx((2.55, 3.8), abs=cell)
    with pytest.raises(ValueError, match='no room for'):
        explore_area(grid, office2.x, office2.y, 2.6)
    with pytest.raises(ValueError, match='not 0.5 m clear'):
        room_bounds(grid, 5.2, 3.0)                 # beside office2's west wall


def _room_with_door(x0: float, y0: float, w: float, h: float, side: int, at: float) -> list[tuple]:
    corners = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    walls = []
    for k in range(4):
        (ax, ay), (bx, by) = corners[k], corners[(k + 1) % 4]
        if k != side:
            walls.append((ax, ay, bx, by))
            continue
        length = math.hypot(bx - ax, by - ay)
        start = at * (length - DOOR - 0.2) + 0.1           # the gap somewhere along the wall
        ux, uy = (bx - ax) / length, (by - ay) / length
        walls.append((ax, ay, ax + ux * start, ay + uy * start))
        walls.append((ax + ux * (start + DOOR), ay + uy * (start + DOOR), bx, by))
    # open space all round (a corridor 5 m wide), which a door that did not close would join
    return walls + [(x0 - 10, y0 - 5, x0 + w + 10, y0 - 5), (x0 - 10, y0 + h + 5, x0 + w + 10, y0 + h + 5)]


@settings(max_examples=60, deadline=None)
@given(w=st.floats(2.5, 8.0), h=st.floats(2.5, 8.0), side=st.integers(0, 3), at=st.floats(0.0, 1.0),
       fx=st.floats(0.0, 1.0), fy=st.floats(0.0, 1.0))
def test_a_generated_room_with_a_door_is_found_whole(w: float, h: float, side: int, at: float,
                                                     fx: float, fy: float) -> None:
    x0, y0 = 11.0, 7.0
    walls = _room_with_door(x0, y0, w, h, side, at)
    grid = build_grid(walls, bounds=(0.0, 0.0, x0 + w + 11.0, y0 + h + 6.0))
    x = x0 + 0.55 + fx * (w - 1.1)                  # at least half a metre (DOOR_HALF) from the walls
    y = y0 + 0.55 + fy * (h - 1.1)
    cell = grid.resolution * 1.5
    assert room_bounds(grid, x, y) == pytest.approx((x0, x0 + w, y0, y0 + h), abs=cell)
    area = explore_area(grid, x, y, 0.6)
    rectangle = Rectangle(area.b, area.h, area.x, area.y, area.theta)
    corners = [rectangle.world(u, v) for u in (0.0, area.h) for v in (-area.b, area.b)]
    for cx, cy in corners:                          # inside the room, 0.6 m from its walls
        assert x0 + 0.6 - cell <= cx <= x0 + w - 0.6 + cell and y0 + 0.6 - cell <= cy <= y0 + h - 0.6 + cell
