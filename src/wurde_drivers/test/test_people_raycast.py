"""The sensors and the base meet people: discs and boxes in the ray casting (wurde_drivers.sim.shapes)
at the right range, in the world at a stamp, in the laser's scan and the sonar ring's echoes, and in
the disc sweep and nearest points the base and its bumpers use."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from wurde_drivers.sim.body import BumperRing, SonarRing
from wurde_drivers.sim.clock import make_rng
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.people import Body, People, Person
from wurde_drivers.sim.raycast import Segments
from wurde_drivers.sim.shapes import Shapes
from wurde_drivers.sim.walk import Walk
from wurde_drivers.sim.world import World

#: A 20 m x 10 m hall with its corner at the origin.
HALL = World([(0, 0, 20, 0), (20, 0, 20, 10), (20, 10, 0, 10), (0, 10, 0, 0)], name='hall')
#: Inside the first hour, where a person of :func:`standing` stands at its point.
NOW = 1000.0


def standing(name: str, body: Body, x: float, y: float, heading: float = 0.0) -> Person:
    """A person who stands at (x, y) facing ``heading`` (a walk of a centimetre, paused for an hour first)."""
    ahead = (x + 0.01 * math.cos(heading), y + 0.01 * math.sin(heading))
    return Person(name, body, Walk(((x, y), ahead), speed=1.0, pause=3600.0))


def test_a_ray_meets_a_disc_and_a_box_at_the_analytic_range() -> None:
    shapes = Shapes([(5.0, 0.0, 1.0)], [(10.0, 3.0, 0.0, 1.0, 0.5), (10.0, -3.0, math.pi / 4, 1.0, 0.5)])
    to_tangent = math.asin(1.0 / 5.0)
    ranges = shapes.cast((0.0, 0.0), [0.0, to_tangent - 1e-6, to_tangent + 1e-6, math.pi,
                                      math.atan2(3.0, 9.0), math.atan2(-3.0, 10.0)])
    # Straight at the disc: its near side at 4 m; just inside the tangent: about the tangent's
    # length, sqrt(25 - 1); past it: a miss; behind: nothing.
    assert ranges[0] == pytest.approx(4.0)
    assert ranges[1] == pytest.approx(math.sqrt(24.0), abs=0.01)
    assert math.isinf(ranges[2]) and math.isinf(ranges[3])
    # A beam parallel to the axis 0.6 m off it meets the circle at x = 5 - sqrt(1 - 0.36).
    assert shapes.cast((0.0, 0.6), [0.0])[0] == pytest.approx(4.2)
    # The box at (10, 3), 2 x 1 m along x: its near end x=9, hit at (9, 3).
    assert ranges[4] == pytest.approx(math.hypot(9.0, 3.0))
    # The box at (10, -3) turned 45 degrees: its corner (10 - 1/sqrt2 + 0.5/sqrt2 ...) — along the
    # ray to its centre, the boundary is where |along| = 1 or |across| = 0.5 in the box's frame.
    direction = np.array([10.0, -3.0]) / math.hypot(10.0, -3.0)
    local = np.array([[math.cos(math.pi / 4), math.sin(math.pi / 4)],
                      [-math.sin(math.pi / 4), math.cos(math.pi / 4)]]) @ direction
    entry = min(1.0 / abs(local[0]), 0.5 / abs(local[1]))      # from the centre back to the boundary
    assert ranges[5] == pytest.approx(math.hypot(10.0, -3.0) - entry)


def test_a_beam_from_inside_reads_zero_and_a_parallel_beam_beside_a_box_misses() -> None:
    shapes = Shapes([(0.0, 0.0, 0.5)], [(5.0, 2.0, 0.0, 1.0, 0.5)])
    assert shapes.cast((0.1, 0.1), [0.0, 2.0]).tolist() == [0.0, 0.0]
    assert shapes.cast((5.2, 2.1), [1.0]).tolist() == [0.0]
    assert math.isinf(shapes.cast((0.0, 2.6), [0.0])[0])          # beside the box, parallel to it
    assert shapes.cast((0.0, 2.5), [0.0])[0] == pytest.approx(4.0)  # along its side: touches it
    assert shapes.cast((0.0, -3.0), [math.pi / 2], max_range=2.0)[0] == 2.0


def test_one_origin_per_beam_gives_the_same_as_one_beam_at_a_time() -> None:
    shapes = Shapes([(3.0, 3.0, 0.4)], [(6.0, 1.0, 0.3, 0.5, 0.2)])
    rng = make_rng(4)
    origins = rng.uniform(0.0, 8.0, size=(50, 2))
    angles = rng.uniform(-math.pi, math.pi, size=50)
    together = shapes.cast(origins, angles)
    alone = [shapes.cast(o, [a])[0] for o, a in zip(origins, angles)]
    assert together.tolist() == pytest.approx(alone)
    with pytest.raises(ValueError):
        shapes.cast(np.zeros((3, 2)), angles)
    with pytest.raises(ValueError):
        shapes.cast((math.nan, 0.0), angles)


boxes = st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi),
                  st.floats(0.05, 2.0), st.floats(0.05, 2.0))


@settings(max_examples=300, deadline=None)
@given(box=boxes, side=st.integers(0, 3), along=st.floats(-1.0, 1.0), gap=st.floats(1e-3, 5.0),
       angles=st.lists(st.floats(-math.pi, math.pi), min_size=1, max_size=20))
def test_a_box_reads_as_its_four_sides_do_as_walls(box: tuple, side: int, along: float, gap: float,
                                                   angles: list[float]) -> None:
    """The slab method against the walls' own raycaster on the box's four sides, from anywhere
    outside the box: ``gap`` beyond one of its sides, near it or far."""
    x, y, heading, half_length, half_width = box
    local = [(half_length + gap, along * half_width), (-half_length - gap, along * half_width),
             (along * half_length, half_width + gap), (along * half_length, -half_width - gap)][side]
    c, s = math.cos(heading), math.sin(heading)
    origin = (x + c * local[0] - s * local[1], y + s * local[0] + c * local[1])
    shapes = Shapes(boxes=[box])
    expected = Segments(shapes.box_edges()).cast(origin, angles)
    assert shapes.cast(origin, angles) == pytest.approx(expected, abs=1e-7)
    towards = math.atan2(y - origin[1], x - origin[0])
    hit = shapes.cast(origin, [towards])[0]                       # the beam at its centre meets it
    assert shapes.nearest(origin)[1][0] - 1e-9 <= hit <= math.dist(origin, (x, y))


@settings(max_examples=300, deadline=None)
@given(disc=st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(0.05, 2.0)),
       origin=st.tuples(st.floats(-10, 10), st.floats(-10, 10)), angle=st.floats(-math.pi, math.pi))
def test_a_disc_reads_where_the_beam_first_reaches_its_radius(disc: tuple, origin: tuple, angle: float) -> None:
    cx, cy, r = disc
    assume(math.dist(origin, (cx, cy)) > r + 1e-6)
    got = Shapes([disc]).cast(origin, [angle])[0]
    u = (math.cos(angle), math.sin(angle))
    if math.isinf(got):                                            # the beam's closest approach
        along = (cx - origin[0]) * u[0] + (cy - origin[1]) * u[1]
        nearest = math.dist((origin[0] + max(along, 0.0) * u[0], origin[1] + max(along, 0.0) * u[1]), (cx, cy))
        assert nearest >= r - 1e-9
    else:
        hit = (origin[0] + got * u[0], origin[1] + got * u[1])
        assert math.dist(hit, (cx, cy)) == pytest.approx(r, abs=1e-7)
        before = (origin[0] + 0.999 * got * u[0], origin[1] + 0.999 * got * u[1])
        assert math.dist(before, (cx, cy)) > r - 1e-9            # nothing of it earlier on the beam


def test_the_world_sees_its_people_where_they_are_at_the_stamp() -> None:
    walker = Person('walker', Body(radius=0.3), Walk(((10.0, 2.0), (10.0, 8.0)), speed=1.0))
    world = HALL.with_people(People((walker,)))
    assert HALL.people == People() and len(world.people) == 1 and world.walls is HALL.walls
    t = 1000 * walker.walk.cycle + 3.0                             # three metres up: (10, 5)
    assert walker.pose_at(t)[:2] == pytest.approx((10.0, 5.0))
    ahead = world.raycast((2.0, 5.0), [0.0], at=t)[0]
    assert ahead == pytest.approx(10.0 - 2.0 - 0.3)
    assert world.raycast((2.0, 5.0), [0.0])[0] == pytest.approx(18.0)            # no stamp: walls only
    assert world.raycast((2.0, 5.0), [0.0], at=t + 2.0)[0] == pytest.approx(18.0)  # it walked on


def test_the_laser_scans_a_disc_and_a_box_at_the_right_range() -> None:
    person = standing('ana', Body(radius=0.25, height=1.7), 6.0, 5.0)
    trolley = standing('trolley', Body(length=1.0, width=0.6, height=1.0), 4.0, 8.0, heading=math.pi / 2)
    world = HALL.with_people(People((person, trolley)))
    model = LaserModel(LaserGeometry(count=181, units='cm', mount_x=0.2), make_rng(1))
    ranges = model.scan(world, 1.8, 5.0, 0.0, at=NOW)              # the laser at (2, 5), facing +x
    assert ranges[90] == pytest.approx(6.0 - 2.0 - 0.25, abs=0.006)           # straight at ana
    # The trolley stands along +y (its length up the hall): its near side x = 3.7, from y 7.5 to 8.5.
    left = math.degrees(math.atan2(3.0, 1.7))                      # the beam to (3.7, 8)
    beam = 90 + round(left)
    angle = math.radians(beam - 90)
    assert ranges[beam] == pytest.approx(1.7 / math.cos(angle), abs=0.006)
    bare = model.scan(HALL, 1.8, 5.0, 0.0, at=NOW)
    assert bare[90] == pytest.approx(18.0, abs=0.006) and bare[beam] > 5.0
    assert model.scan(world, 1.8, 5.0, 0.0).tolist() == bare.tolist()   # no stamp: no people


def test_the_sonars_echo_from_a_person() -> None:
    person = standing('ana', Body(radius=0.25), 5.0, 5.0)
    world = HALL.with_people(People((person,)))
    sonar = SonarRing(count=4, radius=0.3, half_angle=0.0, max_range=8.0)
    ranges = sonar.ranges(world, 3.0, 5.0, 0.0, at=NOW)
    assert ranges[0] == pytest.approx(5.0 - 3.0 - 0.3 - 0.25)   # ahead: the person
    assert ranges[2] == pytest.approx(2.7)                       # behind: the wall x = 0
    assert sonar.ranges(world, 3.0, 5.0, 0.0)[0] == pytest.approx(8.0)   # without a stamp: max range


def test_nearest_points_and_the_bumpers_feel_people() -> None:
    shapes = Shapes([(2.0, 0.0, 0.5)], [(0.0, 3.0, math.pi / 2, 1.0, 0.25)])
    ids, distance, closest = shapes.nearest((0.0, 0.0))
    assert ids.tolist() == [0, 1]
    assert distance.tolist() == pytest.approx([1.5, 2.0])
    assert closest.ravel().tolist() == pytest.approx([1.5, 0.0, 0.0, 2.0])
    assert shapes.nearest((2.1, 0.0))[1][0] == 0.0               # inside: 0, the point itself
    ring = BumperRing(radius=0.35)
    behind = standing('b', Body(radius=0.25), 9.4, 5.0)          # 0.6 behind a robot facing +x
    world = HALL.with_people(People((behind,)))
    assert ring.pressed(world, 10.0, 5.0, 0.0, at=NOW) == (False, True)
    assert ring.pressed(world, 10.0, 5.0, math.pi, at=NOW) == (True, False)
    assert ring.pressed(world, 10.0, 5.0, 0.0) == (False, False)          # no stamp, no people
    assert ring.pressed(world, 10.1, 5.0, 0.0, at=NOW) == (False, False)  # 0.7 away: free


def test_a_disc_moving_into_people_stops_at_first_contact_and_may_leave_them() -> None:
    shapes = Shapes([(5.0, 0.0, 0.5)], [(0.0, 5.0, 0.0, 1.0, 0.5)])
    assert shapes.sweep_circle((0.0, 0.0), (10.0, 0.0), 0.5) == pytest.approx(0.4)   # at x = 4
    assert shapes.sweep_circle((0.0, 0.0), (0.0, 10.0), 0.5) == pytest.approx(0.4)   # box side y = 4.5
    assert shapes.sweep_circle((4.0, 0.0), (4.5, 0.0), 0.5) == 0.0                   # touching: no further
    assert shapes.sweep_circle((4.0, 0.0), (3.0, 0.0), 0.5) == 1.0                   # backing away
    assert shapes.sweep_circle((4.0, 0.0), (4.0, -1.0), 0.5) == 1.0                  # sliding off
    assert shapes.sweep_circle((0.0, 4.0), (0.0, 4.5), 0.5) == 0.0
    assert Shapes().sweep_circle((0.0, 0.0), (1.0, 0.0), 0.5) == 1.0
    # The world takes the nearer of walls and people.
    person = standing('p', Body(radius=0.5), 5.0, 5.0)
    world = HALL.with_people(People((person,)))
    assert world.first_contact((1.0, 5.0), (9.0, 5.0), 0.5, at=NOW) == pytest.approx(3.0 / 8.0)
    assert world.first_contact((1.0, 5.0), (9.0, 5.0), 0.5) == 1.0
    assert world.first_contact((1.0, 5.0), (-1.0, 5.0), 0.5, at=NOW) == pytest.approx(0.25)  # the wall
