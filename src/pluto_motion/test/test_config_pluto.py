"""config/pluto as shipped runs the whole robot under the MCP (issue 12): dummies, localModule,
poseModule and the chain drive → avoid → motion; a client that only knows ``motion/command`` sends a
moveto (42) and a goto (32, passed through to the avoidModule), and the simulator's truth reaches
both goals without coming nearer a wall than the robot's radius."""

from __future__ import annotations

import math
import os
import pathlib
import shutil

from motion_fixture import RADIUS, Commander
from wurde_testing import ChildProcess, find_executable

from pluto_motion.task import TaskResult

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'


def test_config_pluto_runs_moveto_and_goto_through_motion_command(ros_domain: int, tmp_path: pathlib.Path) -> None:
    for name in ('mcp-config.xml', 'mcp-mappings.xml', 'map.xml', 'sim-config.xml'):
        shutil.copy(PLUTO / name, tmp_path / name)
    sim = tmp_path / 'sim-config.xml'
    sim.write_text(sim.read_text().replace('file="map.xml"', f'file="{tmp_path / "map.xml"}"'))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    c = Commander(PLUTO / 'map.xml')
    m = c.motion
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=120)
            c.until(lambda: m.motion_status is not None and m.goto_status not in (None, -10) and c.truths,
                    'the chain runs', timeout=120, every=m.start_activity)
            start = c.truths[-1][:2]
            goal = (start[0] + 3.0, start[1])                           # along the office corridor
            task = m.go_to(*goal, timeout=120)
            c.until(task.is_task_complete, 'moveto', timeout=130)
            assert task.result() is TaskResult.SUCCEEDED, task.reason
            c.until(lambda: math.dist(c.truths[-1][:2], goal) < 0.4, 'the truth at the moveto goal')
            back = (start[0] + 1.0, start[1])
            # The moveto ended with its own simple goto (element[1] -1, then 0 after its stop).
            c.until(lambda: m.goto_status == 0, "the moveto's goto over", timeout=20)
            c.until(lambda: m.goto_status == -1, 'goto under way', timeout=20,
                    every=lambda: m.send(32, [0.5, 1.0], list(back), [1.0]))
            c.until(lambda: m.goto_status == 1, 'goto reached', timeout=90)
            c.until(lambda: math.dist(c.truths[-1][:2], back) < 0.4, 'the truth at the goto goal')
            assert c.closest_to_walls() > RADIUS
    finally:
        c.close()
