"""The manual's DriveProxy example (docs/movement.md) runs as written against the dummy base and the driveModule,
and the robot it commands ends facing north."""

from __future__ import annotations

import math
import os
import pathlib

from drive_fixture import Driver, angle_error, robot, room_config
from wurde_testing import ChildProcess
from wurde_testing.manual import example

def test_drive_proxy_example_turns_the_robot_north(ros_domain: int, tmp_path: pathlib.Path) -> None:
    code = example('drive_proxy', 'python')
    script = tmp_path / 'turn_north.py'
    script.write_text(code)
    directory = room_config(tmp_path)
    driver = Driver()
    try:
        with robot(directory) as processes:
            driver.children = processes
            driver.until(lambda: driver.drive.code == 0 and driver.pose is not None, 'status and truth', timeout=60)
            with ChildProcess([str(script)], env=dict(os.environ)) as client:
                line = client.expect('status', timeout=60)
                assert client.process.wait(timeout=30) == 0
            assert line.startswith('status 0 ')
            driver.until(lambda: driver.drive.code == -10, 'released by the example')
            driver.until(lambda: driver.tv == 0.0 and driver.truths[-1].rv == 0.0, 'at rest', timeout=30)
            assert angle_error(driver.pose[2], math.pi / 2) < 0.03
    finally:
        driver.close()
