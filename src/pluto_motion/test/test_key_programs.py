"""avoid_i and motion_i, Pluto's keyboard programs for the avoidModule and the motionModule (Pluto 5,
6.2, 6.3), in a real pseudo-terminal against the simulated chain: a goto and a moveto typed at their
prompts reach their goals, and a velocity key passes down the chain."""

from __future__ import annotations

import math
import os
import pathlib

from avoid_fixture import Avoider, chain, write_world
from goto_sim import box
from keyboard_fixture import Terminal
from motion_fixture import Commander, pluto, pluto_config
from wurde_testing import find_executable

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'


def test_avoid_i_goto_typed_at_its_prompt(ros_domain: int, tmp_path: pathlib.Path) -> None:
    test = Avoider()
    test.walls = write_world(tmp_path, (10.0, 6.0), box(4.5, 2.5, 5.5, 3.5), (1.5, 3.0, 0.0))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    try:
        with chain(tmp_path) as processes:
            test.children = processes
            test.ready()
            terminal = Terminal([find_executable('pluto_motion', 'avoid_i')], env)
            try:
                terminal.expect(r'status 0 \(normal\)', 60)
                terminal.press('g')
                terminal.expect('goto x y')
                terminal.press('8.5 3\n')
                terminal.expect(r'goto 8\.50 3\.00')
                # Waited on the avoidModule's status while the truth is recorded (track.csv).
                test.until(lambda: test.avoid.goto_status == 1, 'the goto reached', timeout=120)
                terminal.expect(r'goto 1 \(reached\)', 30)
                test.until(lambda: test.pose is not None and math.dist(test.pose[:2], (8.5, 3.0)) < 0.3,
                           'the truth at the goal')
                terminal.press('q')
                assert terminal.process.wait(30) == 0
            finally:
                terminal.close()
    finally:
        test.close()
        (tmp_path / 'track.csv').write_text(''.join(          # what a failure is read from
            f'{t.header.stamp.sec + t.header.stamp.nanosec * 1e-9:.3f},{t.location.x:.3f},{t.location.y:.3f},'
            f'{t.location.theta:.3f}\n' for t in test.truths))


def test_motion_i_moveto_typed_at_its_prompt(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, OFFICE)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    c = Commander(OFFICE)
    try:
        with pluto(directory, '-m', 'map.xml') as processes:
            c.children = processes
            c.until(lambda: c.motion.motion_status is not None and len(c.truths) > 0, 'the chain heard', timeout=120)
            terminal = Terminal([find_executable('pluto_motion', 'motion_i')], env)
            try:
                terminal.expect(r'moveto 0 \(-\) motion 0 \(idle\)', 60)
                terminal.press('up')                                   # passes through to avoid
                terminal.expect(r'command tv \+0\.10')
                terminal.expect(r'status 0 \(normal\) tv \+0\.10')
                terminal.press('m')
                terminal.expect('moveto x y')
                terminal.press('7.5 3\n')
                terminal.expect(r'moveto -1 \(moveto set\)')
                terminal.expect(r'moveto 1 \(at goal\)', 240)
                c.until(lambda: bool(c.truths) and math.dist(c.truths[-1][:2], (7.5, 3.0)) < 0.4,
                        'the truth in office2')
                terminal.press('q')
                assert terminal.process.wait(30) == 0
            finally:
                terminal.close()
    finally:
        c.close()
