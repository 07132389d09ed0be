"""The avoid goto through real processes (dummy base and laser, localModule, driveModule,
avoidModule; exact odometry): it steers round a box between start and goal without touching it and
reports the goal reached; a goal behind a wall with no way round ends stuck, short of the wall."""

from __future__ import annotations

import pathlib

from avoid_fixture import RADIUS, Avoider, chain, write_world
from goto_sim import box

from pluto_motion.task import TaskResult


def test_goto_round_a_box_reaches_the_goal(ros_domain: int, tmp_path: pathlib.Path) -> None:
    obstacle = box(4.5, 2.5, 5.5, 3.5)
    walls = write_world(tmp_path, (10.0, 6.0), obstacle, (1.5, 3.0, 0.0))
    test = Avoider()
    test.walls = walls
    try:
        with chain(tmp_path) as processes:
            test.children = processes
            test.ready()
            task = test.avoid.go_to(8.5, 3.0, 0.5, 1.0)          # cmdFlags 32: sonar and laser
            test.until(task.is_task_complete, 'the goto ended', timeout=120)
            assert task.result() is TaskResult.SUCCEEDED, processes['avoid'].stderr
            x, y, _ = test.pose
            assert abs(x - 8.5) < 0.3 and abs(y - 3.0) < 0.3
            assert max(p[1] for p in ((m.location.x, m.location.y) for m in test.truths)) > 3.5 + RADIUS \
                or min(m.location.y for m in test.truths) < 2.5 - RADIUS      # went round, not through
            assert test.lowest > RADIUS, test.lowest                       # never touched a wall
            codes = [m.element[1] for m in test.avoid_statuses]
            assert -1 in codes and codes[-1] == 1
            assert all(m.element[0] not in (-1, 1, 2) for m in test.statuses)   # no timeout, no bumper
            assert 'Localization/Dead-Reckoning' in processes['avoid'].stderr   # no pose setter: stream 0
    finally:
        test.close()


def test_goto_behind_a_wall_is_stuck(ros_domain: int, tmp_path: pathlib.Path) -> None:
    walls = write_world(tmp_path, (6.0, 4.0), [(3.5, 0.0, 3.5, 4.0)], (1.5, 2.0, 0.0))
    test = Avoider()
    test.walls = walls
    try:
        with chain(tmp_path) as processes:
            test.children = processes
            test.ready()
            task = test.avoid.go_to(5.0, 2.0, 0.5, 1.0)
            test.until(task.is_task_complete, 'the goto ended', timeout=90)
            assert task.result() is TaskResult.FAILED and task.reason == 'goto stuck'
            assert test.avoid.goto_status == 2
            assert test.lowest > RADIUS and test.pose[0] < 3.5 - RADIUS
            test.until(lambda: test.tv == 0.0, 'the robot stopped', timeout=10)
    finally:
        test.close()
