"""drive_i, Pluto's keyboard program for the drive (Pluto 5, 6.1), in a real pseudo-terminal, with the
dummy base and the driveModule as real processes."""

from __future__ import annotations

import os
import pathlib
import re

from drive_fixture import Driver, robot, room_config
from keyboard_fixture import Terminal
from wurde_testing import find_executable


def test_arrow_keys_drive_from_the_working_command(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    driver = Driver()
    try:
        with robot(directory, '-t', '1.5') as children:
            driver.children.update(children)
            terminal = Terminal([find_executable('pluto_motion', 'drive_i')], env)
            try:
                terminal.expect(r'status 0 \(normal\)', 60)            # it started the thread
                terminal.press('up')
                terminal.expect(r'command tv \+0\.10')
                terminal.expect(r'status 0 \(normal\) tv \+0\.10')     # the drive has ramped up
                terminal.press('up')                                   # from the working 0.1
                terminal.expect(r'command tv \+0\.20')
                terminal.expect(r'status 0 \(normal\) tv \+0\.20')     # the drive executes it
                # No key for the timeout: the drive stops the robot, and the next press starts
                # from standstill, not from the 0.2 last sent (the seed's reason for the status).
                terminal.expect(r'status -1 \(timeout\) tv \+0\.00', 30)
                mark = len(terminal.screen)
                terminal.press('up')
                terminal.expect(r'command tv \+0\.10')
                # The drive ramps to what it was sent and holds it until its next timeout: every
                # status until then shows at most 0.10 (a press from the last command sent would
                # have asked for 0.30).
                terminal.expect(r'status -1 \(timeout\)', 30)
                speeds = [float(v) for v in re.findall(r'status 0 \(normal\) tv \+(\d\.\d\d)', terminal.screen[mark:])]
                assert speeds and max(speeds) == 0.10, speeds
                terminal.press('r')
                terminal.expect(r'status -10 \(thread stopped\)')
                terminal.press('q')
                terminal.expect('quit')
                assert terminal.process.wait(30) == 0
            finally:
                terminal.close()
    finally:
        driver.close()
