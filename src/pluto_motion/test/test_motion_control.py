"""The motionModule's command parsing and control (pluto_motion.motion_command, .motion_control),
pure: flags and refusals, the rectangle's geometry (Pluto 6.3's last paragraph), pass-through stops
and resumes a motion, release, unreachable ends with element[2] = 3, a planned moveto steps through
its plan to element[2] = 1 (on an ideal robot), a person standing in the only door makes it wait
(element[2] = 4) and go on when the door clears, or give up after the patience, explore covers its
rectangle and ends at home."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pluto_motion.motion_behaviours import FOLLOW, GOTO, MotionSettings, lawn_mower
from pluto_motion.motion_command import (AT_GOAL, BLOCKED, FOLLOWING, IDLE, IDLE_RECTANGLE, MOVETO_SET, NEARING,
                                         THREAD_STOPPED, UNREACHABLE, CommandRefused, Kind, Rectangle,
                                         parse_command)
from pluto_motion.motion_control import MotionController
from pluto_motion.planning_grid import build_grid

ROOM = [(0, 0, 10, 0), (10, 0, 10, 8), (10, 8, 0, 8), (0, 8, 0, 0)]
NO_POINTS = np.zeros((0, 2))


@pytest.mark.parametrize('flags, position, velocity, force, kind', [
    (-1, [], [], [], Kind.RELEASE), (0, [], [0.2, 0.0], [], Kind.PASS), (32, [1, 2], [0.5, 1], [1], Kind.PASS),
    (42, [3, 4], [], [], Kind.MOVETO), (43, [], [], [], Kind.INVESTIGATE), (44, [], [2, 3], [], Kind.EXPLORE),
    (44, [], [], [], Kind.RESUME), (45, [], [], [], Kind.RESUME), (46, [1, 1], [2, 3], [0.5], Kind.SET_RECTANGLE),
    (46, [], [0, 0], [], Kind.SET_RECTANGLE)])
def test_flags(flags, position, velocity, force, kind) -> None:
    assert parse_command(flags, position, velocity, force).kind is kind


@pytest.mark.parametrize('flags, position, velocity, force, why', [
    (40, [], [], [], 'takes'), (41, [], [], [], 'takes'), (47, [], [], [], 'takes'), (-2, [], [], [], 'takes'),
    (42, [1], [], [], 'needs position'), (42, [math.nan, 1], [], [], 'not finite'),
    (0, [], [math.inf, 0], [], 'not finite'), (46, [1, 1], [2, 3], [], 'needs force'),
    (46, [1, 1], [-2, 3], [0], 'b must be'), (44, [], [2, -1], [], 'positive')])
def test_refusals(flags, position, velocity, force, why) -> None:
    with pytest.raises(CommandRefused, match=why):
        parse_command(flags, position, velocity, force)


def test_rectangle_geometry_as_the_seed_says() -> None:
    """Home (2, 1) facing north (theta pi/2), b = 1.5, h = 4: base from x 0.5 to 3.5 at y 1,
    the far side at y 5."""
    r = Rectangle(1.5, 4.0, 2.0, 1.0, math.pi / 2)
    assert r.contains(2.0, 3.0) and r.contains(0.5, 1.0) and r.contains(3.5, 5.0)
    assert not r.contains(2.0, 0.9) and not r.contains(3.6, 3.0) and not r.contains(2.0, 5.1)
    assert np.allclose(sorted(r.corners()), sorted([(0.5, 1), (3.5, 1), (3.5, 5), (0.5, 5)]))
    points = lawn_mower(r, 2.0, 0.5)
    assert all(r.contains(*p) for p in points)
    assert len(points) == 4 and points[0][1] == pytest.approx(2.0) and points[2][1] == pytest.approx(4.0)


def _controller(grid=None) -> tuple[MotionController, list[str]]:
    warnings: list[str] = []
    return MotionController(grid, MotionSettings(), warn=warnings.append), warnings


def test_rectangle_pass_through_release_and_refusals() -> None:
    c, _ = _controller()
    pose = (5.0, 4.0, 0.0)
    assert c.element3 == IDLE
    assert c.accept(parse_command(46, [5, 1], [2, 4], [math.pi / 2]), pose) == []
    assert c.element3 == IDLE_RECTANGLE
    with pytest.raises(CommandRefused, match='outside the rectangle'):
        c.accept(parse_command(42, [9, 4], [], []), pose)
    c.accept(parse_command(46, [], [0, 0], []), pose)
    assert c.element3 == IDLE and c.rectangle is None
    (request,) = c.accept(parse_command(10, [], [0.3, 0.1], []), pose)
    assert (request.cmd_flags, request.velocity) == (10, (0.3, 0.1))
    (request,) = c.accept(parse_command(-1, [], [], []), pose)
    assert request.cmd_flags == -1 and c.element3 == THREAD_STOPPED
    with pytest.raises(CommandRefused, match='thread stopped'):
        c.accept(parse_command(0, [], [0, 0], []), pose)
    c.start()
    assert c.element3 == IDLE


def test_unreachable_moveto_ends_with_3_and_no_wander() -> None:
    walls = ROOM + [(5, 0, 5, 8)]                       # two closed halves
    c, warnings = _controller(build_grid(walls, bounds=(0, 0, 10, 8)))
    c.accept(parse_command(42, [8, 4], [], []), (2.0, 4.0, 0.0))
    requests = c.step((2.0, 4.0, 0.0), NO_POINTS, None, 0.0)
    assert c.element2 == UNREACHABLE and c.element3 == IDLE and c.behaviour is None
    assert all(r.cmd_flags != GOTO for r in requests)
    assert 'not connected' in c.reason and any('unreachable' in w for w in warnings)


def drive(c: MotionController, pose: tuple[float, float, float], t: float, steps: int = 3000,
          dt: float = 0.1) -> tuple[tuple[float, float, float], float, list, list]:
    """An ideal robot under the controller: the regulator (FOLLOW) turns at once to its heading and
    drives its speed; a goto drives straight to its point at 0.5 m/s.  Returns the last pose and
    time, the poses driven and every request."""
    current, path, requests = None, [pose], []
    for _ in range(steps):
        for r in c.step(pose, NO_POINTS, None, t):
            current = r
            requests.append(r)
        if current is not None and current.cmd_flags == FOLLOW:
            heading, speed = current.position[1], current.velocity[0]
            pose = (pose[0] + speed * dt * math.cos(heading), pose[1] + speed * dt * math.sin(heading), heading)
        elif current is not None and current.cmd_flags == GOTO:
            gx, gy = current.position
            d = math.dist(pose[:2], (gx, gy))
            k = min(1.0, 0.5 * dt / d) if d > 0 else 0.0
            pose = (pose[0] + k * (gx - pose[0]), pose[1] + k * (gy - pose[1]), math.atan2(gy - pose[1], gx - pose[0]))
        path.append(pose)
        t += dt
        if c.behaviour is None:
            break
    return pose, t, path, requests


def test_planned_moveto_follows_the_plan_and_resumes_after_a_stop() -> None:
    grid = build_grid(ROOM + [(5, 0, 5, 6)], bounds=(0, 0, 10, 8))
    c, _ = _controller(grid)
    pose = (2.0, 2.0, 0.0)
    c.accept(parse_command(42, [8, 2], [], []), pose)
    assert c.step(pose, NO_POINTS, None, 0.0) == [] and c.element2 == MOVETO_SET      # planned
    (first,) = c.step(pose, NO_POINTS, None, 0.1)
    # The regulator towards the gap above the wall (north-east), turning on the spot first.
    assert first.cmd_flags == FOLLOW and 0.0 < first.position[1] < math.pi / 2 and c.element3 == FOLLOWING
    assert first.velocity == (0.0,)
    # A pass-through stops it; 45 resumes from where the robot is.
    c.accept(parse_command(0, [], [0, 0], []), pose)
    assert c.behaviour is None and c.element3 == IDLE
    c.accept(parse_command(45, [], [], []), pose)
    pose, _, path, requests = drive(c, pose, 1.0)
    assert c.element2 == AT_GOAL and math.dist(pose[:2], (8.0, 2.0)) <= MotionSettings().reach
    assert all(grid.free_at(x, y) for x, y, _ in path)          # never into the inflated walls
    moving = [r for r in requests if r.cmd_flags != 0]            # the end is a stop (cmdFlags 0)
    assert moving[-1].cmd_flags == GOTO and moving[-1].position == (8.0, 2.0)   # the simple goto last
    assert requests[-1].cmd_flags == 0


def test_nearing_on_the_last_stretch() -> None:
    c, _ = _controller(build_grid(ROOM, bounds=(0, 0, 10, 8)))
    c.accept(parse_command(42, [8, 4], [], []), (2.0, 4.0, 0.0))
    c.step((2.0, 4.0, 0.0), NO_POINTS, None, 0.0)
    (request,) = c.step((2.0, 4.0, 0.0), NO_POINTS, None, 0.1)
    assert request.cmd_flags == FOLLOW and c.element2 == MOVETO_SET
    (request,) = c.step((7.5, 4.0, 0.0), NO_POINTS, None, 0.2)
    assert request.cmd_flags == GOTO and request.position == (8.0, 4.0) and c.element2 == NEARING


#: A person standing in the door of the dividing wall below (x 5, y 6-8): the laser's points on them.
PERSON_IN_DOOR = np.array([(x, y) for x in np.arange(4.8, 5.21, 0.05) for y in np.arange(6.0, 8.01, 0.05)])


def _blocked_at_the_door(patience: float) -> tuple[MotionController, tuple[float, float, float], float]:
    """A moveto through the only door, the robot held where it plans (the person in the door is
    what the laser sees) until it is stuck and finds the way closed round the scan."""
    grid = build_grid(ROOM + [(5, 0, 5, 6)], bounds=(0, 0, 10, 8))
    c = MotionController(grid, MotionSettings(patience=patience), warn=lambda _: None)
    pose, t = (2.0, 2.0, 0.0), 0.0
    c.accept(parse_command(42, [8, 2], [], []), pose)
    requests: list = []
    while c.element2 != BLOCKED and t < 60.0:
        requests += c.step(pose, PERSON_IN_DOOR, None, t)
        t += 0.1
    assert c.element2 == BLOCKED and c.behaviour is not None, 'the moveto must wait, not give up'
    assert requests[-1].cmd_flags == 0 and requests[-1].velocity == (0.0, 0.0)     # stopped
    return c, pose, t


def test_a_person_in_the_door_makes_moveto_wait_then_go_on() -> None:
    c, pose, t = _blocked_at_the_door(patience=60.0)
    for _ in range(100):                                 # 10 s: the person stays, the robot waits
        assert all(r.cmd_flags == 0 for r in c.step(pose, PERSON_IN_DOOR, None, t))
        t += 0.1
    assert c.element2 == BLOCKED and c.behaviour is not None
    pose, _, path, _ = drive(c, pose, t)                 # the person has gone: NO_POINTS
    assert c.element2 == AT_GOAL and math.dist(pose[:2], (8.0, 2.0)) <= MotionSettings().reach


def test_a_door_that_stays_blocked_ends_the_moveto_after_its_patience() -> None:
    c, pose, t = _blocked_at_the_door(patience=5.0)
    start = t
    while c.behaviour is not None and t < start + 30.0:
        c.step(pose, PERSON_IN_DOOR, None, t)
        t += 0.1
    assert c.element2 == UNREACHABLE and 'blocked' in c.reason
    assert 5.0 <= t - start <= 7.0


@pytest.mark.parametrize('home', [(5.0, 1.0), (5.02, 1.03)])   # on a cell border, and between
def test_explore_covers_the_rectangle_and_returns_home(home: tuple[float, float]) -> None:
    grid = build_grid(ROOM, bounds=(0, 0, 10, 8))
    c, _ = _controller(grid)
    pose = (*home, math.pi / 2)
    c.accept(parse_command(44, [], [2.0, 4.0], []), pose)
    assert c.rectangle == Rectangle(2.0, 4.0, *home, math.pi / 2)
    pose, _, path, _ = drive(c, pose, 0.0, steps=20000)
    visited = [p[:2] for p in path]
    # Home is on the rectangle's base: its cell (centre maybe just outside) is not blocked.
    assert c.behaviour is None and c.element2 == AT_GOAL and c.element3 == IDLE_RECTANGLE
    assert math.dist(visited[-1], home) <= MotionSettings().reach
    assert all(c.rectangle.contains(*p, grid.resolution) for p in visited)
    assert max(p[1] for p in visited) == pytest.approx(4.0, abs=MotionSettings().reach)   # up to the second lane


def test_investigate_looks_for_a_scan_then_circles_the_nearest_object() -> None:
    """No scan points yet: investigate keeps approaching (11) for LOOK_S, then ends done (2) with
    nothing to see; with a box's points it sends goto requests round it, 11 then 12."""
    from pluto_motion.motion_behaviours import LOOK_S, Investigate, Situation, Step
    from pluto_motion.motion_command import APPROACHING, CIRCLING, INVESTIGATE_DONE

    said: list[str] = []
    blind = Investigate(MotionSettings(), lambda x, y: True, said.append)
    assert blind.step(Situation((0.0, 0.0, 0.0), NO_POINTS, None, 10.0)) == Step(None, 0, APPROACHING)
    assert blind.step(Situation((0.0, 0.0, 0.0), NO_POINTS, None, 10.0 + LOOK_S - 0.1)).done is False
    end = blind.step(Situation((0.0, 0.0, 0.0), NO_POINTS, None, 10.0 + LOOK_S))
    assert end.done and (end.element2, end.element3) == (INVESTIGATE_DONE, APPROACHING) and 'no object' in said[0]

    box = np.array([(3.0, y) for y in np.linspace(-0.3, 0.3, 7)])       # a face 3 m ahead
    look = Investigate(MotionSettings(), lambda x, y: True, said.append)
    first = look.step(Situation((0.0, 0.0, 0.0), box, None, 0.0))
    assert first.request is not None and first.element3 == APPROACHING
    assert math.dist(first.request.position, (3.0, 0.0)) == pytest.approx(0.3 + MotionSettings().investigate_distance)
    codes = []
    for _ in range(MotionSettings().circle_points + 1):
        target = look.request.position
        step = look.step(Situation((*target, 0.0), box, 1, 1.0))     # each point reached in turn
        codes.append(step.element3)
    assert codes[0] == CIRCLING and step.done and step.element2 == INVESTIGATE_DONE


def test_an_unanswered_goto_is_sent_again() -> None:
    """A goto the avoidModule never answers (the request was lost: written before its reader
    matched) is sent again every RESEND_S until avoid says "goto normal" (-1); then not again."""
    from pluto_motion.motion_behaviours import GOTO_NORMAL
    from pluto_motion.motion_control import RESEND_S

    c, _ = _controller()
    box = np.array([(3.0, y) for y in np.linspace(-0.3, 0.3, 7)])
    c.accept(parse_command(43, [], [], []), (0.0, 0.0, 0.0))
    (first,) = c.step((0.0, 0.0, 0.0), box, 0, 0.0)
    assert first.cmd_flags == GOTO
    assert c.step((0.0, 0.0, 0.0), box, 0, RESEND_S / 2) == []
    assert c.step((0.0, 0.0, 0.0), box, 0, RESEND_S + 0.01) == [first]        # lost: again
    assert c.step((0.0, 0.0, 0.0), box, 0, RESEND_S + 0.5) == []
    assert c.step((0.0, 0.0, 0.0), box, 0, 2 * RESEND_S + 0.02) == [first]
    assert c.step((0.1, 0.0, 0.0), box, GOTO_NORMAL, 2 * RESEND_S + 0.1) == []   # answered
    assert c.step((0.2, 0.0, 0.0), box, GOTO_NORMAL, 10.0) == []
