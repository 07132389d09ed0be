"""The manual's CARMEN program (docs/carmen.md) (pluto_motion.carmen) runs as written as one more module of the whole
simulated Pluto of config/pluto under the MCP: it hears the odometry and the front laser, drives
ahead through the driveModule with CARMEN's velocity command, sends the navigator to office2 and
ends on autonomous_stopped with CARMEN_NAVIGATOR_GOAL_REACHED_v, the simulator's truth at office2."""

from __future__ import annotations

import math
import os
import pathlib
import re
import shutil

from motion_fixture import RADIUS, Commander
from wurde_testing import ChildProcess, find_executable
from wurde_testing.manual import example

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'
OFFICE2 = (7.5, 3.0)


def test_the_carmen_program_drives_and_navigates_the_simulated_pluto(ros_domain: int, tmp_path: pathlib.Path) -> None:
    code = example('carmen_program', 'python')
    script = tmp_path / 'carmen_program.py'
    script.write_text(code)
    script.chmod(0o755)
    for name in ('mcp-config.xml', 'mcp-mappings.xml', 'map.xml', 'sim-config.xml'):
        shutil.copy(PLUTO / name, tmp_path / name)
    config = tmp_path / 'mcp-config.xml'
    config.write_text(config.read_text().replace('</mcp-config>', (
        '  <module name="carmenProgram" managed="unmanaged">\n'
        f'    <binary>{script}</binary>\n    <options>-n carmenProgram</options>\n  </module>\n'
        '</mcp-config>')))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    log = tmp_path / 'mcp-modules' / 'carmenProgram.log'

    def printed(text: str) -> str | None:
        lines = [line for line in (log.read_text() if log.exists() else '').splitlines() if text in line]
        return lines[0] if lines else None
    c = Commander(PLUTO / 'map.xml')
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(config),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=120)
            c.until(lambda: printed('odometry') and c.truths, 'the program and the test hear the robot', timeout=180)
            heard = printed('odometry')
            assert re.search(r'laser 361 readings, closest \d+\.\d\d m', heard), heard
            start = c.truths[-1][:2]
            c.until(lambda: printed('moved'), 'the program drives ahead', timeout=60)
            moved = printed('moved')
            drive_log = tmp_path / 'mcp-modules' / 'driveModule.log'
            assert float(moved.split('moved ')[1].split()[0]) > 0.3, (moved, drive_log.read_text()[-3000:])
            assert math.dist(start, c.truths[-1][:2]) > 0.3
            c.until(lambda: printed('autonomous stopped'), 'autonomous_stopped', timeout=300)
            line = printed('autonomous stopped')
            assert line.endswith('autonomous stopped: CARMEN_NAVIGATOR_GOAL_REACHED_v'), line

            def ended() -> str | None:          # the MCP logs the exit after the program's lines
                after = log.read_text().split(line, 1)[1]
                return next((x for x in after.splitlines() if x.startswith('--- exit code')), None)
            c.until(ended, 'the program ends', timeout=60)
            assert ended() == '--- exit code 0', log.read_text()
            c.until(lambda: math.dist(c.truths[-1][:2], OFFICE2) < 0.4, 'the truth at office2', timeout=30)
            assert c.closest_to_walls() >= RADIUS
            assert mcp.process.poll() is None
    finally:
        c.close()
