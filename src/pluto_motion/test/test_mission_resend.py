"""The mission's goals survive the navigator's restarts (issue 38): ``Mission.visit`` sends its goal
and go again while the navigator's status does not show it driving there — a request lost while
the navigator restarts, or a navigator that came back idle — and ends at once on a refusal.

A navigator stand-in (a Navigator supplier on a second manager, real DDS in one process, stepped on
the mission's turns) loses requests or its goal when told; it drives nowhere, it only answers with
CARMEN's statuses."""

from __future__ import annotations

import time
from collections.abc import Callable

import pytest
from wurde_core import CommsManager, PlanarPoint, PlanarPose
from wurde_core.interfaces import Navigator
from wurde_core.wrappers import GOAL_REACHED, STOP_FAILED, STOP_NONE

import pluto_motion.mission as mission_module
from pluto_motion.mission import Mission
from pluto_motion.mission_log import Goal

PLACES = {'lab': (12.0, 3.5), 'wall': (0.0, 0.0)}


class StandIn:
    """A navigator that drops its first ``drop`` requests, reaches a goal ``drive_turns`` turns
    after go, and refuses the place ``wall``."""

    def __init__(self, drop: int = 0, drive_turns: int = 20) -> None:
        self.manager = CommsManager('navigator')
        self.manager.set_no_sleep()
        self.manager.set_no_heartbeat()
        self.nav = Navigator('Navigator')
        self.nav.set_queue_mode(True)
        self.manager.register_supplier(self.nav)
        self.drop, self.drive_turns = drop, drive_turns
        self.goal: tuple[float, float] | None = None
        self.autonomous, self.reason, self.left = False, STOP_NONE, 0
        self.requests = 0
        #: Called each turn with the stand-in (a test makes it forget its goal here).
        self.hook: Callable[[StandIn], object] = lambda s: None

    def restart(self) -> None:
        """Come back as a navigator restarted before it kept its goal: idle, no goal."""
        self.goal, self.autonomous, self.reason = None, False, STOP_NONE

    def step(self) -> None:
        self.manager.step()
        while self.nav.get_next_request():
            self.requests += 1
            if self.requests <= self.drop:
                continue
            r = self.nav.requests
            written = set(r.ros_message().set_fields)
            place = str(r.goal_place.get_value()) if 'goal_place' in written else ''
            if place:
                self.goal = PLACES[place]
            if 'autonomous' in written and r.autonomous.get_value() and self.goal is not None:
                if self.goal == PLACES['wall']:
                    self.autonomous, self.reason = False, STOP_FAILED
                else:
                    self.autonomous, self.reason, self.left = True, STOP_NONE, self.drive_turns
        if self.autonomous:
            self.left -= 1
            if self.left <= 0:
                self.autonomous, self.reason = False, GOAL_REACHED
        self.hook(self)
        d = self.nav.data
        d.robot = PlanarPose(0.0, 0.0, 0.0)
        d.goal = PlanarPoint(*(self.goal or (0.0, 0.0)))
        d.goal_set = self.goal is not None
        d.autonomous, d.stop_reason = self.autonomous, self.reason
        self.nav.publish_data()


@pytest.fixture
def rig(ros_domain: int, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(mission_module, 'RESEND_S', 0.5)
    manager = CommsManager('mission')
    manager.set_no_sleep()
    manager.set_no_heartbeat()
    mission = Mission(manager, [], '', laser='')
    stand_ins: list[StandIn] = []

    def start(**kwargs) -> StandIn:
        stand_in = StandIn(**kwargs)
        stand_ins.append(stand_in)
        assert mission.nav.wait_for_peers(60.0, channel='request'), 'the stand-in is not matched'
        assert stand_in.nav.wait_for_peers(60.0, channel='data'), 'the mission is not matched'
        return stand_in

    try:
        yield mission, start
    finally:
        for stand_in in stand_ins:
            stand_in.manager.clean_up()
        manager.clean_up()


def goal(name: str) -> Goal:
    return Goal(name, *PLACES[name], started=0.0)


def test_a_goal_lost_by_a_restarting_navigator_is_sent_again(rig) -> None:
    mission, start = rig
    stand_in = start(drop=2)       # the goal and the go of the first send are lost
    assert mission.visit(goal('lab'), 120.0, stand_in.step) == 'reached'
    assert stand_in.requests >= 4


def test_a_navigator_restarted_without_its_goal_is_given_it_again(rig) -> None:
    mission, start = rig
    stand_in = start(drive_turns=40)
    restarted = []

    def forget_once(s: StandIn) -> None:
        if s.autonomous and s.left == 20 and not restarted:
            restarted.append(s.requests)
            s.restart()

    stand_in.hook = forget_once
    assert mission.visit(goal('lab'), 120.0, stand_in.step) == 'reached'
    assert restarted and stand_in.requests > restarted[0], 'the goal was not sent again after the restart'


def test_a_refused_goal_ends_the_visit_at_once(rig) -> None:
    mission, start = rig
    stand_in = start()
    assert mission.visit(goal('wall'), 120.0, stand_in.step) == mission_module.STOP_REASONS[STOP_FAILED]
    assert mission.statuses[-1][:2] == (False, STOP_FAILED)   # it ended on the refusal


def test_a_mission_that_hears_no_pose_says_what_it_hears(rig, monkeypatch: pytest.MonkeyPatch) -> None:
    """A view gone stale is reported once, with each stream's count and writers (a soak's mission
    once heard nothing for minutes while the robot drove).  The warnings are taken where the
    mission gives them (the process's logger may be another test's)."""
    mission, start = rig
    monkeypatch.setattr(mission_module, 'STALL_S', 0.5)
    said: list[str] = []
    monkeypatch.setattr(mission.manager, 'log_warning', said.append)
    stand_in = start()
    deadline = time.monotonic() + 60.0
    while not said:
        assert time.monotonic() < deadline, 'the mission did not say that no Pose came'
        stand_in.step()
        mission._turn(lambda: None)
    [line] = said
    assert line.startswith('no Pose for ')
    assert 'Localization/Pose: 0 received, 0 writers' in line
    assert 'Navigator: ' in line and 'received, 1 writers' in line
    for _ in range(20):
        stand_in.step()
        mission._turn(lambda: None)
    assert len(said) == 1, 'said again within one stall'
