"""The simulated robot among people (wurde_drivers.sim.robot, no ROS): it cannot drive into one,
a person walking into it presses the bumper on that side and stops the base, and each contact is
counted once; the person walks on through the robot, which it does not push."""

from __future__ import annotations

import math

import pytest

from wurde_drivers.sim.clock import make_rng
from wurde_drivers.sim.kinematics import DriveLimits
from wurde_drivers.sim.people import Body, People, Person
from wurde_drivers.sim.robot import RobotSpec, SimRobot
from wurde_drivers.sim.walk import BACK_AND_FORTH, Walk
from wurde_drivers.sim.world import World

HALL = World([(0, 0, 20, 0), (20, 0, 20, 10), (20, 10, 0, 10), (0, 10, 0, 0)], name='hall')
FAST = DriveLimits(max_tv=1.0, max_rv=2.0, tv_accel=0.0, rv_accel=0.0)
DT = 0.02
RADIUS = 0.35          # RobotSpec's bumper ring


def robot_among(people: list[Person], start: tuple[float, float, float], now: float = 0.0) -> SimRobot:
    world = HALL.with_people(People(tuple(people)))
    return SimRobot(world, RobotSpec(limits=FAST), make_rng(1), start=start, now=now)


def test_the_robot_driving_into_a_standing_person_stops_at_it_and_bumps() -> None:
    # Ana stands at (8, 5) for the first hour (her walk of a centimetre begins after it).
    ana = Person('ana', Body(radius=0.25), Walk(((8.0, 5.0), (8.01, 5.0)), speed=1.0, pause=3600.0))
    robot = robot_among([ana], (5.0, 5.0, 0.0))
    robot.command(0.5, 0.0)
    for _ in range(1000):
        robot.step(DT)
        if robot.bumper_stop:
            break
    assert robot.bumper_stop and robot.bumpers == (True, False)
    assert robot.truth.x == pytest.approx(8.0 - 0.25 - RADIUS, abs=1e-9)     # touching her
    assert robot.truth.tv == 0.0 and robot.tv_command == 0.0
    assert robot.person_contacts == 1
    robot.command(0.5, 0.0)                                    # further into her: refused
    robot.step(DT)
    assert robot.truth.x == pytest.approx(8.0 - 0.25 - RADIUS, abs=1e-9) and robot.person_contacts == 1
    robot.command(-0.5, 0.0)                                   # backing away: free, contact over
    for _ in range(10):
        robot.step(DT)
    assert robot.truth.x < 7.3 and robot.bumpers == (False, False) and robot.person_contacts == 1


@pytest.mark.parametrize('heading, bumpers', [(0.0, (True, False)), (math.pi, (False, True))])
def test_a_person_walking_into_a_standing_robot_presses_a_bumper_once_per_contact(
        heading: float, bumpers: tuple[bool, bool]) -> None:
    """Ben walks up and down across the robot's path, 0.1 m ahead of its centre (robot facing
    +x) or behind it (facing -x): the front or the back bumper."""
    ben = Person('ben', Body(radius=0.25), Walk(((10.1, 2.0), (10.1, 8.0)), speed=1.0, pause=1.0,
                                                mode=BACK_AND_FORTH))
    robot = robot_among([ben], (10.0, 5.0, heading))
    pressed, onsets = [], []
    for _ in range(round(2 * ben.walk.cycle / DT)):             # two rounds: four passes
        robot.step(DT)
        if robot.new_person_contacts:
            assert robot.new_person_contacts == [0]
            onsets.append(robot.now)
        if any(robot.bumpers):
            pressed.append(robot.bumpers)
        assert (robot.truth.x, robot.truth.y) == (10.0, 5.0)   # never pushed
    assert robot.person_contacts == 4 and len(onsets) == 4
    assert set(pressed) == {bumpers}
    # Each contact begins as his body reaches the robot's: centres sqrt(0.61^2 - 0.1^2) apart in y
    # (the bumpers feel 1 cm beyond the footprint), walking at 1 m/s from y = 2 after a 1 s pause.
    gap = math.sqrt((RADIUS + 0.01 + 0.25) ** 2 - 0.1 ** 2)
    # Up from y = 2 (a 1 s pause, then 1 m/s), down from y = 8 (after 6 s up and a 1 s pause).
    expected = [4.0 - gap, 11.0 - gap]
    expected += [t + ben.walk.cycle for t in expected]
    assert onsets == pytest.approx(expected, abs=DT + 1e-9)
    # While he passes through (about 2 * 0.61 m at 1 m/s) the bumper stays pressed, counted once.
    assert len(pressed) * DT == pytest.approx(4 * 2 * gap, abs=4 * 2 * DT)


def test_a_person_touching_a_moving_robot_stops_it() -> None:
    """Cleo (a trolley, a box) crosses the robot's way as it drives: the bumper trips.  She
    passes y = 5 every 4 s; the robot, at 0.2 m/s, needs 6 s to cross her lane."""
    cleo = Person('cleo', Body(length=0.8, width=0.5, height=1.0),
                  Walk(((9.0, 8.0), (9.0, 2.0)), speed=1.5, pause=0.0, mode=BACK_AND_FORTH))
    robot = robot_among([cleo], (5.0, 5.0, 0.0), now=0.0)
    stopped = False
    for _ in range(2000):
        if not robot.bumper_stop:
            robot.command(0.2, 0.0)
        robot.step(DT)
        if robot.new_person_contacts:
            stopped = True
            assert robot.truth.tv == 0.0 and robot.bumper_stop and any(robot.bumpers)
            _, gaps, _ = robot.world.shapes_at(robot.now).nearest((robot.truth.x, robot.truth.y))
            assert gaps[0] <= RADIUS + 0.01
            break
    assert stopped and robot.person_contacts == 1
