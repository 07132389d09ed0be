"""Active scanning (pluto_motion.active_scan), pure: where the motionModule points the wrist for each
behaviour, fed by real behaviours stepping on simulated scans; and moveto by ray following on a
map (``rays_only``, the motionModule's ``-R``)."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
from test_ray_follow import _box, _points
from wurde_drivers.sim.world import World

from pluto_motion.active_scan import GROUND, LEFT, SIDE, SWEEP_S, aim_for, is_wall_follow
from pluto_motion.motion_behaviours import Investigate, MotionSettings, Situation
from pluto_motion.motion_command import CIRCLING, FOLLOWING, NEARING, SCANNING, Kind, MotionCommand
from pluto_motion.motion_control import MotionController
from pluto_motion.planning_grid import grid_from_map_file

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'
CORRIDOR = World(_box(0, 0, 20, 6))


def test_wall_follow_is_avoid_type_3_and_turns_the_wrist_left() -> None:
    assert [f for f in range(40) if is_wall_follow(f)] == [3, 13, 23, 33]
    assert not is_wall_follow(43)
    control = MotionController(None)
    control.accept(MotionCommand(Kind.PASS, 33, (0.8,), (0.3,)), None)
    aim = control.aim(None, 0.0)
    assert aim is not None and (aim.pan, aim.tilt) == (LEFT, 0.0)
    control.accept(MotionCommand(Kind.PASS, 0, (), (0.0, 0.0)), None)      # a stop: the wrist is let go
    assert control.aim(None, 0.0) is None
    control.accept(MotionCommand(Kind.PASS, 13, (0.8,), (0.3,)), None)
    control.accept(MotionCommand(Kind.RELEASE, -1), None)
    assert control.aim(None, 0.0) is None


def test_ray_following_looks_right_and_left_in_turn_and_at_the_ground_near_the_goal() -> None:
    control = MotionController(grid_from_map_file(OFFICE), rays_only=True)
    control.accept(MotionCommand(Kind.MOVETO, 42, (8.0, 3.0)), None)
    moveto = control.behaviour
    assert moveto is not None and moveto.planner is None              # rays, though there is a map
    pose = (2.0, 3.0, 0.0)
    codes = []
    for t in (0.0, 0.1):
        control.step(pose, _points(CORRIDOR, pose), None, t)
        codes.append(control.element3)
        aim = control.aim(pose, t)
        assert aim is not None
        if control.element3 == SCANNING:
            assert (aim.pan, aim.tilt) == (0.0, 0.0)
    assert codes == [SCANNING, FOLLOWING]
    sides = {math.copysign(1.0, control.aim(pose, t).pan) for t in (0.5, 0.5 + SWEEP_S)}
    assert sides == {1.0, -1.0}
    assert all(abs(control.aim(pose, t).pan) == SIDE for t in (0.5, 0.5 + SWEEP_S))
    near = aim_for(moveto, FOLLOWING, NEARING, False, pose, 0.0)
    assert near is not None and (near.pan, near.tilt) == (0.0, GROUND)


def test_planned_moveto_looks_ahead_and_the_planner_stays_the_default() -> None:
    control = MotionController(grid_from_map_file(OFFICE))
    control.accept(MotionCommand(Kind.MOVETO, 42, (7.5, 3.0)), None)
    assert control.behaviour is not None and control.behaviour.planner is not None
    pose = (3.0, 7.5, 0.0)
    control.step(pose, np.zeros((0, 2)), None, 0.0)
    aim = control.aim(pose, 0.0)
    assert aim is not None and (aim.pan, aim.tilt) == (0.0, 0.0)


@pytest.mark.parametrize('wrist', [True, False])
def test_investigate_arm_step_turns_the_wrist_to_the_object(wrist: bool) -> None:
    said: list[str] = []
    box = World(_box(0, 0, 20, 12) + _box(6.0, 5.5, 7.0, 6.5))
    investigate = Investigate(MotionSettings(), lambda x, y: True, said.append, wrist=wrist)
    pose = (3.0, 6.0, 0.0)
    step = investigate.step(Situation(pose, _points(box, pose), None, 0.0))
    assert step.request is not None and investigate.centre is not None
    assert investigate.centre == pytest.approx((6.0, 6.0), abs=0.3)   # the face the laser sees
    target = step.request.position
    arrived = (target[0], target[1], math.pi / 2)                       # facing north at the first point
    step = investigate.step(Situation(arrived, _points(box, arrived), None, 1.0))
    assert step.element3 == CIRCLING and investigate.approached
    assert said == (['investigate: no arm on this robot; the wrist turns to the object instead'] if wrist else
                    ['investigate: the arm step (unfold the arm) is not available on this robot'])
    aim = aim_for(investigate, CIRCLING, 0, False, arrived, 1.0)
    bearing = math.atan2(investigate.centre[1] - arrived[1], investigate.centre[0] - arrived[0]) - arrived[2]
    assert aim is not None and aim.pan == pytest.approx(math.remainder(bearing, math.tau)) and aim.tilt == GROUND
    assert abs(aim.pan) > 1.0                                          # the object is to the side
