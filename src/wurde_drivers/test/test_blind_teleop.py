"""blind_teleop under the MCP with config/blind-teleop (guide 1.1.5): the joystick emulator's
translate axis drives the simulated ATRV Jr forward (the simulator's truth), the quickpan and
quicktilt axes reach the PTU, the stop button stops the robot; stopped by the MCP while it
drives, blind_teleop stops the robot as it goes; started again, it reads the stick's state from
the init events and drives on; a joystick that vanishes stops the robot too, and the quit button
(on the joystick come back) ends blind_teleop with status 0.

A copy of the shipped configuration (so that logs stay out of the tree) with the joystick FIFO and
the map at the test's own paths; the test plays the user at the joystick through the
``joystick_emulator`` program's stdin, plays the set-up's external SafePTUServer (a PTUnit
supplier that records the requests) and watches ``HollowayRFlexTruth``.
"""

from __future__ import annotations

import math
import os
import pathlib
import time
from collections.abc import Callable

import pytest
from wurde_core import CommsManager
from wurde_core.interfaces import Egomotion, ObstacleAvoider, PTUnit
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
SHIPPED = ROOT / 'config' / 'blind-teleop'
#: The laserAvoider's states (ObstacleAvoiderTransport data): stopped, and goal reached.
IDLE, REACHED = 0, 3
FILES = ('mcp-config.xml', 'mcp-mappings.xml', 'sim-config.xml', 'joystick-config.xml')


def shipped_copy(directory: pathlib.Path) -> str:
    """config/blind-teleop in ``directory``, its joystick FIFO there too; returns the FIFO's path."""
    fifo = str(directory / 'js0')
    for name in FILES:
        text = (SHIPPED / name).read_text()
        if name == 'mcp-config.xml':
            assert '-j /tmp/wurde-joystick' in text
        text = text.replace('/tmp/wurde-joystick', fifo)
        (directory / name).write_text(text.replace('../maps/', f'{ROOT}/config/maps/'))
    return fifo


def last_run(log: pathlib.Path) -> str:
    """A module's log from its last start (the MCP's registration pass ran it once before)."""
    return log.read_text().rsplit(' start: ', 1)[-1] if log.exists() else ''


def test_the_joystick_drives_points_stops_and_quits_blind_teleop(ros_domain: int,
                                                          tmp_path: pathlib.Path) -> None:
    fifo = shipped_copy(tmp_path)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    manager = CommsManager('TeleopWatcher')
    manager.set_no_sleep()
    truth = Egomotion('HollowayRFlexTruth')
    truth.set_queue_mode(True)
    manager.register_consumer(truth)
    ptu = PTUnit('SafePTUServer')
    manager.register_supplier(ptu)
    avoider = ObstacleAvoider('SimpleAvoider')        # to watch its state, never to command it
    avoider.set_queue_mode(True)
    manager.register_consumer(avoider)
    states: list[tuple[float, int]] = []           # monotonic time, the avoider's state
    path: list[tuple[float, float, float]] = []    # monotonic time, x, y
    pan_tilt: list[tuple[float, float]] = []      # the PTU requests
    log = tmp_path / 'mcp-modules' / 'BlindTeleop.log'
    emulator = [find_executable('wurde_drivers', 'joystick_emulator'), '-p', fifo]

    def until(predicate: Callable[[], bool], what: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while not predicate():
            assert mcp.process.poll() is None, f'{what}: the MCP exited: {mcp.stderr[-3000:]}'
            assert time.monotonic() < deadline, (f'{what}: not within {timeout} s; last truth '
                                                 f'{path[-1:]}; PTU {pan_tilt[-1:]}; BlindTeleop '
                                                 f'log: {last_run(log)[-2000:]}')
            manager.step()
            while truth.get_next_data():
                path.append((time.monotonic(), truth.data.location.x(), truth.data.location.y()))
            while avoider.get_next_data():
                states.append((time.monotonic(), int(avoider.data.state)))
            while ptu.get_next_request():
                pan_tilt.append((ptu.requests.pan.get_value(), ptu.requests.tilt.get_value()))
            manager.wait(0.05)

    def still_for(seconds: float) -> bool:
        """The truth moved less than 1 cm over the last ``seconds``."""
        if not path or path[-1][0] - path[0][0] < seconds:
            return False
        recent = [p for p in path if p[0] >= path[-1][0] - seconds]
        return math.dist(recent[0][1:], recent[-1][1:]) < 0.01

    def stopped_not_arrived(since: float) -> bool:
        """Since ``since`` the avoider was told to stop: it went to IDLE and never reached the goal
        it was driving to (it would have, ~1 m ahead, had nobody told it)."""
        after = [state for at, state in states if at >= since]
        return bool(after) and after[-1] == IDLE and REACHED not in after

    def changes(since: float) -> list[int]:
        """The avoider's states since ``since``, each change once (for failure messages)."""
        seen = [state for at, state in states if at >= since]
        return [state for i, state in enumerate(seen) if i == 0 or seen[i - 1] != state]

    def moved_from(where: tuple[float, float]) -> float:
        return math.dist(path[-1][1:], where)

    def controller(*args: str) -> None:
        with ChildProcess([find_executable('wurde_mcp', 'mcp_controller'), *args], env=env) as tool:
            tool.expect('mcp_controller: sent', timeout=30)

    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', 'mcp-config.xml', '-m',
                           'mcp-mappings.xml', '-a'], env=env, cwd=str(tmp_path)) as mcp:
            with ChildProcess(emulator, env=env, cwd=str(tmp_path)) as stick:
                stick.expect('joystick "Saitek P990 Dual Analog Pad"', timeout=60)
                stick.expect('reader 1 opened the joystick', timeout=90)   # blind_teleop reads it
                until(lambda: bool(path), 'the simulator running', 60)
                start = path[-1][1:]
                stick.send('axis translate -16000')        # half forward: a point ~1 m ahead
                until(lambda: path[-1][1] - start[0] > 0.5, 'the robot driven forward', 90)
                assert abs(path[-1][2] - start[1]) < 0.1, 'it went sideways'
                stick.send('axis quickpan 32767')          # a quarter turn clockwise
                stick.send('axis quicktilt 16384')
                until(lambda: bool(pan_tilt) and pan_tilt[-1][0] == pytest.approx(-math.pi / 4)
                      and pan_tilt[-1][1] == pytest.approx(0.1, abs=1e-4), 'the PTU requests', 30)
                stick.send('press stop')                   # stick still forward: stop wins
                until(lambda: still_for(1.0), 'the robot stopped by the stop button', 30)
                stopped = path[-1][1:]
                stick.send('release stop')
                until(lambda: moved_from(stopped) > 0.3, 'the robot going again', 30)
                # The MCP stops BlindTeleop while it drives: its last word stops the robot.
                since = time.monotonic()
                controller('stop', 'BlindTeleop')
                until(lambda: '--- exit code' in last_run(log), 'blind_teleop stopped', 30)
                assert last_run(log).rstrip().endswith('--- exit code 0'), last_run(log)[-2000:]
                until(lambda: still_for(1.0), 'the robot stopped with blind_teleop', 30)
                assert stopped_not_arrived(since), changes(since)
                assert 'quitting: avoider told to stop\n' in last_run(log)
                stick.expect('reader 1 closed it', timeout=10)
                controller('start', 'BlindTeleop')
                stick.expect('reader 2 opened the joystick', timeout=60)
                stopped = path[-1][1:]                      # the stick is still forward, and the
                until(lambda: moved_from(stopped) > 0.3,   # init events tell the new reader so
                      'the robot driven by the restarted blind_teleop', 60)
                since = time.monotonic()
            # The emulator ended: its FIFO closed and removed, the joystick vanished.
            until(lambda: still_for(1.0), 'the robot stopped when the joystick vanished', 30)
            assert 'the joystick stopped: avoider told to stop' in last_run(log)
            assert stopped_not_arrived(since), changes(since)
            stopped = path[-1][1:]
            with ChildProcess(emulator, env=env, cwd=str(tmp_path)) as stick:
                stick.expect('reader 1 opened the joystick', timeout=30)   # reopened, retried
                stick.send('press quit')
                until(lambda: '--- exit code' in last_run(log), 'blind_teleop ended', 30)
                assert last_run(log).rstrip().endswith('--- exit code 0'), last_run(log)[-2000:]
                assert 'quit button' in last_run(log)
                stick.expect('reader 1 closed it', timeout=10)
            assert moved_from(stopped) < 0.02                # nothing stale moved it
    finally:
        manager.clean_up()


def test_bad_joystick_configs_and_scripts_end_the_programs_with_file_and_line(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    bad = tmp_path / 'joystick-config.xml'
    bad.write_text('<joystick-config>\n<joystick name="J">\n<axis id="b5" name="tilt"/>\n'
                   '</joystick>\n</joystick-config>\n')
    script = tmp_path / 'drive.txt'
    script.write_text('axis 1 -16000\nwait 1\naxis rudder 5\n')
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path))
    for argv, where in (([find_executable('wurde_drivers', 'blind_teleop'), '-j', str(tmp_path / 'js')],
                         f'{bad}:3: attribute id="b5" of <axis> is not an integer'),
                        ([find_executable('wurde_drivers', 'joystick_emulator'), '-p',
                          str(tmp_path / 'js'), '-c', str(ROOT / 'config' / 'blind-teleop' /
                                                          'joystick-config.xml'), '-f', str(script)],
                         f'{script}:3: no axis named "rudder"')):
        with ChildProcess(argv, env=env) as program:
            assert program.process.wait(timeout=60) == 2
        assert where in program.stderr, program.stderr
    assert not (tmp_path / 'js').exists()
