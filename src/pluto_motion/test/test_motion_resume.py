"""A restarted motionModule carries on (issue 38): the state it keeps (pluto_motion.motion_resume)
read back into a new controller gives the same thread, rectangle and motion (a moveto, what an
explore had left, an investigate started over); JSON in between, as in the resume file."""

from __future__ import annotations

import json

from pluto_motion.motion_behaviours import Explore, Investigate, Moveto
from pluto_motion.motion_command import MOVETO_SET, NO_MOVETO, THREAD_STOPPED, Kind, MotionCommand, Rectangle
from pluto_motion.motion_control import MotionController
from pluto_motion.motion_resume import restore, state_of


def _through_file(control: MotionController) -> MotionController:
    again = MotionController(None)
    said = restore(again, json.loads(json.dumps(state_of(control))))
    assert isinstance(said, str)
    return again


def test_a_running_moveto_is_driven_on_by_the_next_process() -> None:
    control = MotionController(None)
    control.start()
    control.accept(MotionCommand(Kind.MOVETO, 42, (3.0, 4.5)), (0.0, 0.0, 0.0))
    again = _through_file(control)
    assert again.running and isinstance(again.behaviour, Moveto)
    assert again.behaviour.goal == (3.0, 4.5)
    assert again.element2 == MOVETO_SET and again.element3 != THREAD_STOPPED


def test_a_paused_moveto_stays_paused_and_the_rectangle_is_kept() -> None:
    control = MotionController(None)
    control.start()
    control.rectangle = Rectangle(2.0, 5.0, 1.0, -1.0, 0.5)
    control.accept(MotionCommand(Kind.MOVETO, 42, (1.5, 0.0)), (1.0, -1.0, 0.0))
    control.accept(MotionCommand(Kind.PASS, 0, (), (0.0, 0.0)), None)     # a stop: resumable
    again = _through_file(control)
    assert again.behaviour is None and isinstance(again.paused, Moveto)
    assert again.rectangle == Rectangle(2.0, 5.0, 1.0, -1.0, 0.5)
    again.accept(MotionCommand(Kind.RESUME, 45), None)
    assert isinstance(again.behaviour, Moveto) and again.behaviour.goal == (1.5, 0.0)


def test_a_released_module_comes_back_stopped_and_bad_state_is_ignored() -> None:
    control = MotionController(None)
    control.start()
    control.accept(MotionCommand(Kind.RELEASE, -1), None)
    again = _through_file(control)
    assert not again.running and again.behaviour is None and again.element3 == THREAD_STOPPED
    broken = MotionController(None)
    assert restore(broken, {'running': 'yes', 'motion': {'kind': 'moveto', 'goal': [1.0, float('nan')]},
                            'rectangle': {'b': 1}}) == 'nothing running'
    assert broken.running and broken.behaviour is None and broken.element2 == NO_MOVETO   # a fresh start's


def test_an_explore_goes_on_with_the_points_it_had_left() -> None:
    control = MotionController(None)
    control.start()
    control.accept(MotionCommand(Kind.EXPLORE, 44, (), (2.0, 4.0), rectangle=Rectangle(2.0, 4.0, 0.0, 0.0, 0.0)),
                   (1.0, 1.0, 0.5))
    explore = control.behaviour
    assert isinstance(explore, Explore) and len(explore.points) > 2
    explore.points.pop(0)                                   # one lane point visited
    again = _through_file(control)
    assert isinstance(again.behaviour, Explore)
    assert again.behaviour.points == explore.points and again.rectangle == control.rectangle
    assert again.behaviour.points[-1] == (again.rectangle.x, again.rectangle.y)     # home last


def test_an_investigate_starts_over() -> None:
    control = MotionController(None)
    control.start()
    control.accept(MotionCommand(Kind.INVESTIGATE, 43), (0.0, 0.0, 0.0))
    again = _through_file(control)
    assert isinstance(again.behaviour, Investigate) and again.behaviour.targets is None
