"""CARMEN's parameters end to end: a real ``param_daemon`` process, the client API
(Programming with CARMEN 6) in this process, ``param_tool`` as a user runs it, and rclpy's
parameter client where a user would run ``ros2 param``.  Every wait has a deadline."""

from __future__ import annotations

import contextlib
import pathlib
import re
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from wurde_core import CommsManager
from wurde_core.carmen_param import CarmenParams, Param, ParamExit, ParamType, ParamTypeError
from wurde_testing import ChildProcess, find_executable
from wurde_testing.manual import example
from wurde_testing.parameters import ParameterTool

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'
#: Longest wait for a daemon to come up, a tool to finish or a change to arrive (loaded machine).
DEADLINE = 30.0

INI = """\
# test parameters
[*]
avoid_safety_distance 0.3
robot_max_t_vel   0.5
robot_count       3
robot_name        Pluto the robot   # a string with spaces
laser_flipped     off

[pluto]
robot_max_t_vel   0.3
laser_flipped     on
"""


@contextlib.contextmanager
def daemon(tmp_path: pathlib.Path, *args: str, text: str = INI) -> Iterator[ChildProcess]:
    """A param_daemon on ``tmp_path/carmen.ini`` (found by the search order: cwd)."""
    (tmp_path / 'carmen.ini').write_text(text)
    with ChildProcess([find_executable('wurde_mcp', 'param_daemon'), *args], cwd=tmp_path) as child:
        child.expect('param_daemon ready', timeout=DEADLINE * 2)
        yield child


@contextlib.contextmanager
def client(name: str = 'carmen_test') -> Iterator[tuple[CommsManager, CarmenParams]]:
    manager = CommsManager(name)
    manager.set_no_heartbeat()
    params = CarmenParams(manager)
    try:
        yield manager, params
    finally:
        params.close()
        manager.clean_up()


def tool(*args: str) -> tuple[int, str, str]:
    """Run the installed ``param_tool``: (status, stdout, stderr)."""
    with ChildProcess([find_executable('wurde_mcp', 'param_tool'), *args]) as child:
        status = child.process.wait(timeout=DEADLINE * 2)
        child.stop()
        return status, child.stdout, child.stderr


def poll(manager: CommsManager, params: CarmenParams, done: Callable[[], bool], what: str) -> None:
    """A module's loop until ``done()``: apply parameter changes, wait on the manager."""
    deadline = time.monotonic() + DEADLINE
    while not done():
        assert time.monotonic() < deadline, f'{what} not within {DEADLINE} s'
        params.update()
        manager.wait(0.05)


def test_get_converts_warns_and_keeps_types(ros_domain: int, tmp_path: pathlib.Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    with daemon(tmp_path, '-a') as child, client() as (manager, params):
        assert params.get_double('robot_max_t_vel') == 0.3
        # one context (one DDS participant) per process: the client's node is in the module's
        assert params._node.context is manager.context is not None
        assert child.stdout.splitlines()[:5] == ['avoid_safety_distance 0.3',
                                                 'laser_flipped on', 'robot_count 3',
                                                 'robot_max_t_vel 0.3',
                                                 'robot_name Pluto the robot']
        assert params.get_double('robot_max_t_vel') == 0.3
        assert params.get_int('robot_count') == 3
        assert params.get_double('robot_count') == 3.0            # an int is a fine double
        assert params.get_onoff('laser_flipped') is True
        assert params.get_string('laser_flipped') == 'on'
        assert params.get_string('robot_count') == '3'
        assert params.get_string('robot_name') == 'Pluto the robot'
        with pytest.raises(ParamTypeError, match="robot_name is 'Pluto the robot', not an int"):
            params.get_int('robot_name')
        with pytest.raises(ParamTypeError, match='not an int'):
            params.get_int('robot_max_t_vel')
        capsys.readouterr()
        assert params.get_int('robot_max_speed') is None
        assert 'WARNING: get_int' in capsys.readouterr().err
        params.allow_unfound_variables(True)
        assert params.get_int('robot_max_speed') is None
        assert capsys.readouterr().err == ''
        params.set_module('robot')
        assert params.get_double('max_t_vel') == 0.3
        assert params.get_onoff('laser_flipped') is True          # fully qualified still works

        user = ParameterTool('/param_daemon')                     # what `ros2 param` does
        try:
            assert {'robot.max_t_vel', 'laser.flipped', 'reread'} <= set(user.names())
            taken, reason = user.set('robot.max_t_vel', 'fast')
            assert not taken and 'type' in reason
            assert user.get('robot.max_t_vel') == [0.3]
            assert user.set('robot.max_t_vel', 1) == (True, '')    # an int for a double
            assert user.get('robot.max_t_vel') == [1.0]
            assert user.set('laser.flipped', 'yes')[0] is False
            taken, reason = user.set('robot.max_speed', 1.0)      # rclpy's own refusal
            assert not taken and 'undeclared' in reason
        finally:
            user.close()
        assert params.get_double('max_t_vel') == 1.0


def test_subscriptions_follow_param_tool(ros_domain: int, tmp_path: pathlib.Path) -> None:
    class Robot:
        max_t_vel = 0.0

    robot, laser, seen = Robot(), {'flipped': None}, []

    def changed(module: str, variable: str, value: Any) -> None:
        seen.append((module, variable, value, robot.max_t_vel))   # the target is set first

    with daemon(tmp_path) as _child, client() as (manager, params):
        params.subscribe_double('robot', 'max_t_vel', (robot, 'max_t_vel'), changed)
        params.subscribe_onoff('laser', 'flipped', (laser, 'flipped'))
        assert tool('set', 'robot_max_t_vel', '0.25')[:2] == (0, 'robot_max_t_vel 0.25\n')
        poll(manager, params, lambda: bool(seen), 'the change of robot_max_t_vel')
        assert seen == [('robot', 'max_t_vel', 0.25, 0.25)] and robot.max_t_vel == 0.25
        assert tool('set', 'laser_flipped', 'OFF')[0] == 0
        poll(manager, params, lambda: laser['flipped'] is False, 'the change of laser_flipped')

        status, _out, err = tool('set', 'robot_max_t_vel', 'fast')
        assert status == 1 and 'Wrong parameter type' in err
        status, _out, err = tool('set', 'robot_max_speed', '1')
        assert status == 1 and 'no such parameter' in err
        assert tool('get', 'robot_max_t_vel')[:2] == (0, 'robot_max_t_vel 0.25\n')
        status, _out, err = tool('get', 'robot_max_speed')
        assert status == 1 and 'robot_max_speed' in err
        assert robot.max_t_vel == 0.25 and len(seen) == 1


def test_install_params(ros_domain: int, tmp_path: pathlib.Path,
                        capsys: pytest.CaptureFixture[str]) -> None:
    class Settings:
        max_t_vel = 0.0
        count = 0
        flipped = False

    settings = Settings()
    table = [Param('robot', 'max_t_vel', ParamType.DOUBLE, (settings, 'max_t_vel'), True),
             Param('robot', 'count', ParamType.INT, (settings, 'count')),
             Param('laser', 'flipped', 'onoff', (settings, 'flipped'))]
    with client() as (_manager, params):                 # -h needs no daemon
        with pytest.raises(ParamExit) as caught:
            params.install_params(['robot', '-h'], table)
        assert caught.value.code == 0
        out = capsys.readouterr().out.splitlines()
        assert re.fullmatch(r'  robot_max_t_vel\s+double\s+yes', out[2])
        assert re.fullmatch(r'  laser_flipped\s+onoff\s+no', out[4])
    with daemon(tmp_path) as _child, client() as (_manager, params):
        rest = params.install_params(['robot', '-n', 'x', '-count', '7', '-other', '1'], table)
        assert rest == ['robot', '-n', 'x', '-other', '1']
        assert (settings.max_t_vel, settings.count, settings.flipped) == (0.3, 7, True)
        capsys.readouterr()
        with pytest.raises(ParamExit) as caught:
            params.install_params(['robot'],
                                  [*table, Param('robot', 'max_speed', ParamType.DOUBLE)])
        assert caught.value.code == 1 and 'robot_max_speed' in str(caught.value)
        assert 'robot_max_speed' in capsys.readouterr().err
        with pytest.raises(ParamExit, match="robot_name is 'Pluto the robot', not a double"):
            params.install_params(['robot'], [Param('robot', 'name', ParamType.DOUBLE)])
        params.allow_unfound_variables(True)
        unfound = [Param('robot', 'max_speed', 'double')]
        assert params.install_params(['robot'], unfound) == ['robot']


def test_reread_applies_a_good_file_and_refuses_a_broken_one(ros_domain: int,
                                                             tmp_path: pathlib.Path) -> None:
    with daemon(tmp_path) as child, client() as (manager, params):
        ini = tmp_path / 'carmen.ini'
        ini.write_text(INI.replace('robot_max_t_vel   0.3', 'robot_max_t_vel   0.35')
                       + 'navigator_goal home\n')
        assert tool('reread')[0] == 0
        poll(manager, params, lambda: params.get_double('robot_max_t_vel') == 0.35,
             'the re-read value')
        child.expect('2 changed (navigator.goal, robot.max_t_vel)', timeout=DEADLINE)
        assert params.get_string('navigator_goal') == 'home'

        ini.write_bytes(INI.encode() + b'robot_owner M\xfcller\n')   # line 12: not UTF-8
        status, _out, err = tool('reread')
        assert status == 1 and f'{ini}:12: not UTF-8 (byte 0xfc)' in err
        ini.write_text(INI.replace('robot_count       3', 'robot_count       many'))
        status, _out, err = tool('reread')
        assert status == 1 and f'{ini}:5: robot_count ' in err and 'served as int' in err
        ini.write_text(INI.replace('[pluto]', '[atrv]'))
        status, _out, err = tool('reread')
        assert status == 1 and 'no robot [pluto] (robots: atrv)' in err
        assert params.get_double('robot_max_t_vel') == 0.35
        assert params.get_int('robot_count') == 3

        ini.write_text(INI + 'robot_max_t_vel 0.9\n')              # twice in [pluto], line 12
        assert tool('reread')[0] == 0                             # CARMEN's rule: the later wins
        poll(manager, params, lambda: params.get_double('robot_max_t_vel') == 0.9,
             'the later of two values')
        child.expect('1 changed (robot.max_t_vel)', timeout=DEADLINE)
        assert tool('reread')[0] == 0                             # the same warning: told once
        child.expect('0 changed', timeout=DEADLINE)
    warning = (f'param_daemon: warning: {ini}:12: robot_max_t_vel is set again in [pluto] (first '
               'on line 10): this later value wins')
    assert child.stderr.count(warning) == 1, child.stderr


def test_install_file_and_robot_choice(ros_domain: int, tmp_path: pathlib.Path) -> None:
    two = INI + '\n[atrv]\nrobot_max_t_vel 1.5\n'
    (tmp_path / 'carmen.ini').write_text(two)
    with ChildProcess([find_executable('wurde_mcp', 'param_daemon')], cwd=tmp_path) as child:
        assert child.process.wait(timeout=DEADLINE * 2) == 2
        child.stop()
        assert 'robots (pluto, atrv): choose one with -R ROBOT' in child.stderr
    with daemon(tmp_path, '-R', 'atrv', text=two), client() as (_manager, params):
        assert params.get_double('robot_max_t_vel') == 1.5
        other = tmp_path / 'other.ini'
        other.write_text('[*]\nrobot_count 5\nrobot_max_t_vel 2\nrobot_wheels 4\n')
        status, out, err = tool('install', str(other))
        assert status == 1 and f'{other}:4: ' in err and '1 refused' in out
        assert (params.get_int('robot_count'), params.get_double('robot_max_t_vel')) == (5, 2.0)


@pytest.mark.parametrize(('args', 'reason'), [
    (['-M', '0', str(OFFICE)], 'param_daemon: -M: '),
    (['room.xml'], 'room.xml:3: '),
])
def test_a_bad_map_or_resolution_is_refused(ros_domain: int, tmp_path: pathlib.Path,
                                            args: list[str], reason: str) -> None:
    """The map argument is served, so a broken map or a grid of no size is refused at start."""
    (tmp_path / 'carmen.ini').write_text(INI)
    (tmp_path / 'room.xml').write_text('<?xml version="1.0"?>\n<map name="room" version="1.0">\n'
                                       '  <wal/>\n</map>\n')
    with ChildProcess([find_executable('wurde_mcp', 'param_daemon'), '-R', 'pluto', *args],
                      cwd=tmp_path) as child:
        assert child.process.wait(timeout=DEADLINE * 2) == 2
        child.stop()
    assert reason in child.stderr, child.stderr


def test_readme_example_runs_against_a_daemon(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The manual's install_params example (docs/carmen.md) as a module: daemon values, a -name
    override, and a subscribed change."""
    script = tmp_path / 'carmen_example.py'
    script.write_text(example('carmen_params', 'python'))
    with daemon(tmp_path):
        with ChildProcess([str(script), '-safety_distance', '0.25']) as module:
            module.expect('max_t_vel 0.3 flipped True safety_distance 0.25', timeout=DEADLINE * 2)
            assert tool('set', 'robot_max_t_vel', '0.4')[0] == 0
            module.expect('robot_max_t_vel is now 0.4', timeout=DEADLINE)
            assert module.stop() == 0


def test_a_module_s_tunables_follow_the_daemon_across_its_restart(ros_domain: int,
                                                                   tmp_path: pathlib.Path) -> None:
    """wurde_core.carmen_tunables in a module's own loop (the ``param_daemon`` option): a tunable
    takes carmen.ini's value; after the daemon is killed and started again on another file, the
    module finds the new one and takes its value.  ``tuned_module_gain`` splits as carmen.ini's
    names do: module ``tuned``, variable ``module_gain``."""
    manager = CommsManager('tuned_module')
    manager.set_no_heartbeat()
    manager.config.set_option('param_daemon', 'on')
    gain = manager.tunable('gain', 1.5, 'how hard to steer, rad/s per rad', 0.0, 10.0)

    def turn_until(done: Callable[[], bool], what: str) -> None:
        deadline = time.monotonic() + DEADLINE
        while not done():
            assert time.monotonic() < deadline, f'{what} not within {DEADLINE} s'
            manager.step()
            manager.wait(0.05)

    try:
        with daemon(tmp_path, text='[*]\ntuned_module_gain 2.5\n') as first:
            turn_until(lambda: gain.value == 2.5, "the first daemon's gain")
            first.process.kill()
            assert first.process.wait(timeout=DEADLINE) is not None
        with daemon(tmp_path, text='[*]\ntuned_module_gain 4.0\n'):
            turn_until(lambda: gain.value == 4.0, "the restarted daemon's gain")
    finally:
        manager.clean_up()
