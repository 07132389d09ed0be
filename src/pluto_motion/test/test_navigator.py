"""CARMEN's navigator (Programming with CARMEN 4.2.1, 4.3) on config/pluto under the MCP: a client
with the Navigator wrapper sets a goal by place name and goes (autonomous, then stopped with goal
reached, the truth at the place); an unknown place has no effect; go at the goal is autonomous
for a moment and then goal reached; stop while driving stops with user stopped and the robot halts;
a goal in an off-limits region or on a wall fails (stop reason 3) with the reason in the log."""

from __future__ import annotations

import math
import os
import pathlib
import shutil
from typing import Any

from motion_fixture import RADIUS, Commander
from wurde_core.interfaces import Navigator
from wurde_core.wrappers import GOAL_REACHED, STOP_FAILED, USER_STOPPED
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'
OFFICE2 = (7.5, 3.0)


class Statuses:
    """Every navigator status taken in: (autonomous, stop_reason, goal_set, goal)."""

    def __init__(self, nav: Any) -> None:
        self.nav = nav
        self.seen: list[tuple[bool, int, bool, tuple[float, float]]] = []

    def take(self) -> list:
        while self.nav.get_next_data():
            d = self.nav.data
            self.seen.append((bool(d.autonomous), int(d.stop_reason), bool(d.goal_set), (d.goal.x(), d.goal.y())))
        return self.seen

    def since(self, mark: int) -> list:
        return self.take()[mark:]


def listen(manager: Any) -> tuple[Any, Statuses]:
    """A queue-mode Navigator consumer of ``manager`` and its :class:`Statuses`."""
    nav = Navigator('Navigator')
    nav.set_queue_mode(True)
    manager.register_consumer(nav)
    return nav, Statuses(nav)


def _follows(statuses: list, first: tuple[bool, int], then: tuple[bool, int]) -> bool:
    """Whether a status ``first`` (autonomous, stop_reason) came and later a status ``then``."""
    pairs = [x[:2] for x in statuses]
    return first in pairs and then in pairs[pairs.index(first) + 1:]


def test_the_navigator_goes_to_places_by_name_and_stops_when_told(ros_domain: int, tmp_path: pathlib.Path) -> None:
    for name in ('mcp-config.xml', 'mcp-mappings.xml', 'map.xml', 'sim-config.xml'):
        shutil.copy(PLUTO / name, tmp_path / name)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    c = Commander(PLUTO / 'map.xml')
    nav, s = listen(c.manager)
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=120)
            c.until(lambda: nav.peers('request') > 0 and s.take() and c.truths, 'the navigator answers',
                    timeout=120)
            # An unknown place has no effect: two statuses later no goal is set.
            mark = len(s.take())
            assert nav.set_goal_place('nowhere')
            c.until(lambda: len(s.since(mark)) >= 2, 'statuses after the unknown place')
            assert not s.seen[-1][2]
            log = tmp_path / 'mcp-modules' / 'navigator.log'
            c.until(lambda: "no place 'nowhere'" in log.read_text(), 'the warning in the log')

            # By place name: autonomous, then stopped with goal reached at office2.
            mark = len(s.take())
            assert nav.set_goal_place('office2') and nav.go()
            c.until(lambda: any(a for a, *_ in s.since(mark)), 'autonomous', timeout=30)
            c.until(lambda: (st := s.since(mark)) and not st[-1][0] and st[-1][1] != 0, 'stopped', timeout=200)
            assert s.seen[-1][:3] == (False, GOAL_REACHED, True) and s.seen[-1][3] == OFFICE2
            assert math.dist(c.truths[-1][:2], OFFICE2) < 0.4
            assert c.closest_to_walls() >= RADIUS

            # Go while at the goal: momentarily autonomous, then goal reached (4.3).
            mark = len(s.take())
            assert nav.go()
            c.until(lambda: _follows(s.since(mark), (True, 0), (False, GOAL_REACHED)),
                    'momentarily autonomous, then goal reached', timeout=30)

            # Stop while driving: user stopped, and the robot halts.
            mark = len(s.take())
            truth_mark = len(c.truths)
            assert nav.set_goal(3.0, 7.5) and nav.go()
            c.until(lambda: any(a for a, *_ in s.since(mark)) and math.dist(c.truths[-1][:2], OFFICE2) > 0.5,
                    'driving back', timeout=60)
            mark = len(s.take())
            assert nav.stop()
            c.until(lambda: (st := s.since(mark)) and st[-1][:2] == (False, USER_STOPPED), 'user stopped',
                    timeout=30)
            c.until(lambda: abs(c.speeds[-1]) < 0.01, 'the robot halted', timeout=30)
            assert len(c.truths) > truth_mark

            # Goals that cannot be reached — in the lab's off-limits work cell, on a wall — each
            # end with stop reason 3 (failed) and a log line with the planner's reason.
            for goal in ((14.0, 3.5), (5.0, 6.3)):
                mark = len(s.take())
                assert nav.set_goal(*goal) and nav.go()
                c.until(lambda: (st := s.since(mark)) and st[-1][:2] == (False, STOP_FAILED), f'{goal} failed',
                        timeout=60)
                c.until(lambda: f'goal {goal} not reached' in log.read_text(), 'the reason in the log')
            assert 'unreachable' in log.read_text()
            assert mcp.process.poll() is None
    finally:
        c.close()
