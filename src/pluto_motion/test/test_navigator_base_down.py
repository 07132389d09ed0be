"""A goal while the base is down (issue 13's bad input): the navigator, with no MCP to idle it,
ends a drive whose base dies with stop reason 3 (failed) and a log line that says why, stops the
chain, and answers a ``go`` sent while the base is still down the same way.  Nothing crashes.

Real processes: config/pluto's dummies, localModule, poseModule, the chain and the navigator on
the office map; the base is killed with SIGKILL, as a crash would."""

from __future__ import annotations

import math
import os
import pathlib
import signal

from motion_fixture import PLUTO, Commander, pluto, pluto_config, program
from test_navigator import listen
from wurde_core.wrappers import STOP_FAILED
from wurde_testing import ChildProcess

from pluto_motion.navigator import BASE_WAIT_S

DOWN = 'not reached: the base is down: no odometry from PlutoBase'


def _said(child: ChildProcess, text: str) -> list[str]:
    """The child's Logger warnings (on stderr) that contain ``text``."""
    return [line for line in child.stderr.splitlines() if line.startswith('[WARN] navigator:') and text in line]


def test_a_goal_while_the_base_is_down_fails_with_its_reason(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, PLUTO / 'map.xml')
    c = Commander(PLUTO / 'map.xml')
    nav, s = listen(c.manager)
    try:
        with pluto(directory, '-m', 'map.xml') as processes, \
                program('pluto_motion', 'navigator', directory, '-n', 'navigator', '-m', 'map.xml') as navigator:
            c.children = dict(processes, navigator=navigator)
            c.until(lambda: nav.peers('request') > 0 and s.take() and c.truths, 'the navigator answers',
                    timeout=120)

            # Driving to office2, the base dies: failed, with the reason, and the chain stops.
            mark = len(s.take())
            start = c.truths[-1]
            assert nav.set_goal_place('office2') and nav.go()
            c.until(lambda: any(a for a, *_ in s.since(mark)) and math.dist(c.truths[-1][:2], start[:2]) > 0.3,
                    'driving to office2', timeout=120)
            base = c.children.pop('base')
            os.kill(base.process.pid, signal.SIGKILL)
            base.stop()
            mark = len(s.take())
            c.until(lambda: (st := s.since(mark)) and st[-1][:2] == (False, STOP_FAILED), 'failed: base down',
                    timeout=60)
            c.until(lambda: len(_said(navigator, DOWN)) == 1, 'the reason in the log')
            c.until(lambda: c.motion.motion_status == 0, 'the motion stopped')

            # A go while the base is still down: failed again at once, with its own log line.
            mark = len(s.take())
            assert nav.set_goal(3.0, 3.0) and nav.go()
            c.until(lambda: (st := s.since(mark)) and st[-1][:2] == (False, STOP_FAILED) and st[-1][3] == (3.0, 3.0),
                    'the second goal failed', timeout=60)
            c.until(lambda: len(_said(navigator, DOWN)) == 2, 'its own line in the log')
            line = _said(navigator, DOWN)[-1]
            assert '(3.0, 3.0)' in line and float(line.rsplit('for ', 1)[1].split()[0]) > BASE_WAIT_S
            assert all(p.process.poll() is None for p in c.children.values())
    finally:
        c.close()
