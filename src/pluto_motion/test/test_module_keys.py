"""The keyboard programs of the other modules (Pluto 5: "each module has a simple user interface that
allows control from the keyboard"): base_i, wrist_i, sick_i, dmu_i, gpsmeter, slam_i and local_i,
each in a real pseudo-terminal against the simulated Pluto's dummies (and the real localModule and
slamModule), all real processes."""

from __future__ import annotations

import contextlib
import os
import pathlib
import re
import time

import pytest
from drive_fixture import program, room_config
from keyboard_fixture import Terminal
from wurde_testing import ChildProcess, find_executable

DUMMIES = {'PlutoBase': 'dummy_base', 'PlutoLaser': 'dummy_sick', 'PlutoWrist': 'dummy_wrist',
           'PlutoDMU': 'dummy_dmu', 'PlutoGPS': 'dummy_gps'}


def _env(directory: pathlib.Path) -> dict[str, str]:
    return dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory),
                WURDE_DATA_DIR=str(directory))


@contextlib.contextmanager
def _terminal(name: str, directory: pathlib.Path):
    terminal = Terminal([find_executable('pluto_motion', name)], _env(directory))
    try:
        yield terminal
        terminal.press('q')
        terminal.expect('quit')
        assert terminal.process.wait(30) == 0
    finally:
        terminal.close()


@contextlib.contextmanager
def _dummies(directory: pathlib.Path, names):
    with contextlib.ExitStack() as stack:
        for name in names:
            stack.enter_context(program('wurde_drivers', DUMMIES[name], directory, '-n', name))
        yield stack


def test_device_programs_in_a_terminal(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)       # a 6 m x 4 m room, the robot at (3, 2) facing east
    with _dummies(directory, DUMMIES):
        with _terminal('base_i', directory) as base:
            # The calibration shows once the base has published its command state (at a command).
            base.expect(r'base x \+0\.00 y \+0\.00 theta \+0\.00 tv \+0\.00 rv \+0\.00 calibration \S+( \S+)? '
                        r'bumpers 00 sonar \d\.\d\d battery', 90)
            base.press('up')
            base.expect(r'command tv \+0\.10 m/s rv \+0\.00')
            base.expect(r'tv \+0\.10 rv \+0\.00 calibration 1\.0000 1\.0000')
            base.expect(r'tv \+0\.00 rv \+0\.00', 30)     # the base's watchdog: nothing repeated
            moved = float(re.findall(r'base x \+(\d\.\d\d)', base.screen)[-1])
            assert moved >= 0.05, base.screen
            base.press('k')
            base.expect('distance and rotation scales')
            base.press('x\n')
            base.expect('2 numbers wanted; nothing sent')
            base.press('k')
            base.expect('distance and rotation scales')
            base.press('1.01 0.99\n')
            base.expect(r'calibration 1\.0100 0\.9900 sent')
            base.expect(r'calibration 1\.0100 0\.9900 bumpers', 30)       # the base took it
            base.press('?')
            base.expect('keys: arrows drive, space stops, k calibration, q quit')
        with _terminal('wrist_i', directory) as wrist:
            wrist.expect(r'wrist pan \+0\.00 tilt \+0\.00', 60)
            wrist.press('left')
            wrist.expect(r'wrist command pan \+0\.10 tilt \+0\.00')
            wrist.expect(r'wrist pan \+0\.10 tilt \+0\.00 target \+0\.10 \+0\.00', 30)
            wrist.press('p')
            wrist.expect('pan tilt')
            wrist.press('-0.5 0.2\n')
            wrist.expect(r'wrist pan -0\.50 tilt \+0\.20 target -0\.50 \+0\.20', 30)
        with _terminal('sick_i', directory) as sick:
            sick.expect(r'laser 361 points', 60)
            sick.press('s')
            scan = sick.expect(r'scan 361 points ahead (\S+) m nearest (\S+) m at (\S+) deg')
            # The laser 0.2 m ahead of the centre: the east wall 2.8 m minus what base_i drove;
            # the nearest are the side walls, 2 m to the left or right.
            assert float(scan.group(1)) == pytest.approx(2.8 - moved, abs=0.05), sick.screen
            assert float(scan.group(2)) == pytest.approx(2.0, abs=0.05), sick.screen
            assert abs(float(scan.group(3))) > 60.0, sick.screen
            sick.press('r')
            sick.expect(r'rwi 181 points ahead')
        with _terminal('dmu_i', directory) as dmu:
            dmu.expect(r'dmu heading [+-]0 pitch [+-]0 roll [+-]0 deg', 60)
            dmu.press('d')
            filtered = dmu.expect(r'dmu theta (\S+) phi (\S+) psi (\S+) rad rates (\S+) (\S+) (\S+) rad/s '
                                  r'accelerations (\S+) (\S+) (\S+) m/s2')
            assert float(filtered.group(9)) == pytest.approx(9.81, abs=0.3), dmu.screen     # gravity, z up
            dmu.press('r')
            dmu.expect(r'raw theta \+0\.0000 ')                            # the raw state has no heading
        with _terminal('gpsmeter', directory) as gps:
            fix = gps.expect(r'gps x (\S+) y (\S+) m satellites 8 quality 2 good', 60)
            # The dummy's grid is the map's frame: the antenna (mounted within 0.1 m of the centre)
            # where base_i left the robot.
            assert float(fix.group(1)) == pytest.approx(3.0 + moved, abs=0.2), gps.screen
            assert float(fix.group(2)) == pytest.approx(2.0, abs=0.2), gps.screen
            gps.press('l')
            gps.expect(r'gps latitude 59\.349\d+ longitude 18\.070\d+ altitude')


def test_navigation_programs_in_a_terminal(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)
    env = _env(directory)
    with _dummies(directory, ['PlutoBase', 'PlutoLaser', 'PlutoWrist', 'PlutoDMU']), \
            ChildProcess([find_executable('pluto_nav', 'local_module')], env=env), \
            ChildProcess([find_executable('pluto_nav', 'slam_module')], env=env):
        with _terminal('slam_i', directory) as slam:
            slam.expect(r'slam running 0 saving 0 walls 0 landmarks 0 maps saved 0', 90)
            slam.press('a')
            slam.expect('slam start')
            slam.expect(r'slam running 1 ', 60)
            slam.expect(r'slam running 1 saving 0 walls [1-9]', 60)     # something to save
            slam.press('m')
            slam.expect(r'slam save map')
            slam.expect(r'slam running 1 saving 0 walls \d+ landmarks \d+ maps saved 1', 60)
            slam.press('s')
            slam.expect(r'slam running 0 saving 0 walls \d+ landmarks \d+ maps saved 2', 60)
        assert (directory / 'slam-map.xml').is_file()
        with _terminal('local_i', directory) as local:
            local.expect(r'local odometry 1 dmu 1 setter 0 refused 0', 90)
            local.press('p')
            pose = r'x (\S+) y (\S+) theta (\S+) setter (\S+)'
            # Where the map's start place is (the slamModule's corrections and the DMU's noise
            # move it by millimetres), then the pose set by hand.
            for n in (0, 3):
                found = local.expect(rf'{n} Localization/\S+ {pose}')
                assert [float(v) for v in found.groups()[:3]] == pytest.approx([3.0, 2.0, 0.0], abs=0.03)
            local.press('e')
            local.expect('x y theta')
            local.press('3.5 2.5 0.2\n')
            local.expect(r'set pose \+3\.500 \+2\.500 \+0\.2000')
            local.expect(r'local odometry 1 dmu 1 setter -1 refused 0', 30)
            # The status may say setter -1 before the next Pose (10 Hz) has reached local_i: ask
            # again until it shows the pose set (or 30 s have passed).
            deadline = time.monotonic() + 30
            while True:
                local.press('p')
                found = [float(v) for v in local.expect(rf'3 Localization/Pose {pose}').groups()]
                if found[3] == -1 or time.monotonic() > deadline:
                    break
            assert found == pytest.approx([3.5, 2.5, 0.2, -1], abs=0.01)
