"""The manual's AvoidProxy example (docs/movement.md) runs as written against the simulated chain (dummy base and laser,
localModule, driveModule, avoidModule): the goto round a box ends SUCCEEDED with the robot at the
goal, never closer to a wall than its radius."""

from __future__ import annotations

import os
import pathlib

from avoid_fixture import RADIUS, Avoider, chain, write_world
from goto_sim import box
from wurde_testing import ChildProcess
from wurde_testing.manual import example

def test_avoid_proxy_example_reaches_the_goal_round_the_box(ros_domain: int, tmp_path: pathlib.Path) -> None:
    code = example('avoid_proxy', 'python')
    script = tmp_path / 'goto_box.py'
    script.write_text(code)
    script.chmod(0o755)
    test = Avoider()
    test.walls = write_world(tmp_path, (10.0, 6.0), box(4.5, 2.5, 5.5, 3.5), (1.5, 3.0, 0.0))
    try:
        with chain(tmp_path) as processes:
            test.children = processes
            test.ready()
            with ChildProcess([str(script)], env=dict(os.environ)) as client:
                line = client.expect('result', timeout=120)
                assert client.process.wait(timeout=30) == 0
            assert line.startswith('result SUCCEEDED'), line
            test.until(lambda: test.tv == 0.0, 'at rest', timeout=30)
            x, y, _ = test.pose
            assert abs(x - 8.5) < 0.3 and abs(y - 3.0) < 0.3
            assert test.lowest > RADIUS
    finally:
        test.close()
