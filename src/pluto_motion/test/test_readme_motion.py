"""The manual's MotionProxy example (docs/movement.md) runs as written against the whole simulated Pluto on the office
map (dummies with odometry noise, localModule, poseModule, drive, avoid, motion with the map): it
ends SUCCEEDED in office2, through the room's 0.9 m door, never closer to a wall than the robot's
radius."""

from __future__ import annotations

import math
import os
import pathlib

from motion_fixture import RADIUS, Commander, pluto, pluto_config
from wurde_testing import ChildProcess
from wurde_testing.manual import example

ROOT = pathlib.Path(__file__).resolve().parents[3]
OFFICE = ROOT / 'config' / 'maps' / 'office.xml'


def test_motion_proxy_example_reaches_office2(ros_domain: int, tmp_path: pathlib.Path) -> None:
    code = example('motion_proxy', 'python')
    script = tmp_path / 'go_to_office2.py'
    script.write_text(code)
    script.chmod(0o755)
    directory = pluto_config(tmp_path, OFFICE)
    c = Commander(OFFICE)
    try:
        with pluto(directory, '-m', 'map.xml') as processes:
            c.children = processes
            c.until(lambda: c.motion.motion_status is not None and len(c.truths) > 0, 'the chain heard', timeout=120)
            with ChildProcess([str(script)], env=dict(os.environ)) as client:
                line = client.expect('result', timeout=300)
                assert client.process.wait(timeout=30) == 0
            assert line.startswith('result SUCCEEDED'), line
            # The truth the test queued meanwhile, read in order up to the robot in office2.
            c.until(lambda: bool(c.truths) and math.dist(c.truths[-1][:2], (7.5, 3.0)) < 0.4, 'the truth in office2',
                    timeout=60)
            assert c.closest_to_walls() > RADIUS
    finally:
        c.close()
