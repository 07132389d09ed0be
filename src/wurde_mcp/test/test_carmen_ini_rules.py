"""carmen.ini by CARMEN's reading rules (param_daemon.c): what CARMEN's own carmen.ini and its
robots' files hold — a name without a value, a stray ``>``, names that are not module_variable,
``[expert]``, robot names with ``+`` in any case, a name set twice — loads, each oddity warned
about once with file:line; through the real ``param_daemon`` with CARMEN's ``--robot=NAME``."""

from __future__ import annotations

import pathlib

import pytest
from wurde_idl.errors import ConfigError
from wurde_testing import ChildProcess, find_executable
from wurde_testing.parameters import ParameterTool

from wurde_mcp.carmen import choose_robot, read_ini
from wurde_mcp.carmen.daemon import carmen_options

#: Longest wait for the daemon to come up or exit (a loaded machine).
DEADLINE = 60.0

#: Every quirk of CARMEN's carmen.ini (line 145: ``xsens_adapt``), of a robot's file (a stray
#: ``>``), and of how CARMEN reads sections, with the line numbers the warnings name.
QUIRKS = """\
robot_stray            1                    # 1: before any section header
[*]
robot_max_t_vel        0.5
robot_use_laser        on
robot_rectangular      0          # right now used only by robotgraph
xsens_dev              /dev/ttyUSB0
xsens_adapt
>
maxspeed               1
laser_front-dev        /dev/ttyS0
camera_dev             /dev/video#0 the rest is a comment
robot_acceleration     0.3

[Pluto]
robot_max_t_vel        0.3
robot_rectangular      0
robot_rectangular      1
ROBOT_USE_LASER        off
robot_acceleration     0.5

[p2d8+]
robot_max_t_vel        0.4

[p2d8+dual]
robot_max_t_vel        0.45

[pluto
robot_hidden           1

[EXPERT]
robot_theta_gain       1.0
robot_acceleration     0.7
"""

#: (line, the warning's reason) of every warning :data:`QUIRKS` gives, in file order.
WARNINGS = [
    (1, "'robot_stray' is before the first section header: it and the lines up to the header are "
        'skipped'),
    (7, 'xsens_adapt has no value: skipped'),
    (8, '> has no value: skipped'),
    (9, "name 'maxspeed' is not module_variable (it needs a _ between a module and a variable): "
        'skipped'),
    (10, "name 'laser_front-dev' has characters other than letters, digits and _ or more than 254 "
         'of them (a ROS 2 parameter name here): skipped'),
    (17, 'robot_rectangular is set again in [Pluto] (first on line 16): this later value wins'),
    (18, 'ROBOT_USE_LASER is robot_use_laser of line 4 (names are not case sensitive): served as '
         'robot_use_laser'),
    (27, "section header '[pluto' is not [*], [expert] or [robot]: the lines under it are skipped"),
    (32, "robot_acceleration of [EXPERT] overrides [Pluto] line 19: the later line wins"),
]


@pytest.fixture
def quirks(tmp_path: pathlib.Path) -> pathlib.Path:
    path = tmp_path / 'carmen.ini'
    path.write_text(QUIRKS)
    return path


def test_the_quirks_load_as_carmen_loads_them(quirks: pathlib.Path) -> None:
    ini = read_ini(quirks)
    assert [(w.path, w.line, w.reason) for w in ini.warnings] == [
        (str(quirks), line, reason) for line, reason in WARNINGS]
    assert ini.robots() == ['Pluto', 'p2d8+', 'p2d8+dual']       # '+' is part of a name
    pluto = ini.parameters('PLUTO')                                # robots in any case
    assert {name: (e.value, e.line, e.expert) for name, e in pluto.items()} == {
        'camera_dev': ('/dev/video', 11, False),                   # '#' anywhere: a comment
        'robot_acceleration': ('0.7', 32, True),                   # file order: [EXPERT] last
        'robot_max_t_vel': ('0.3', 15, False),
        'robot_rectangular': ('1', 17, False),                     # the later of two
        'robot_theta_gain': ('1.0', 31, True),
        'robot_use_laser': ('off', 18, False),                     # the first spelling names it
        'xsens_dev': ('/dev/ttyUSB0', 6, False),
    }
    assert ini.parameters('p2d8+')['robot_max_t_vel'].value == '0.4'
    assert ini.parameters('p2d8+DUAL')['robot_max_t_vel'].value == '0.45'
    default = ini.parameters(None)                                 # CARMEN's "default robot"
    assert default['robot_acceleration'].value == '0.7' and 'robot_hidden' not in default
    assert choose_robot(ini, 'pluto') == 'Pluto'
    with pytest.raises(ConfigError, match=r'3 robots \(Pluto, p2d8\+, p2d8\+dual\): choose one'):
        choose_robot(ini, None)
    with pytest.raises(ConfigError,
                       match=r'no robot \[b21\] \(robots: Pluto, p2d8\+, p2d8\+dual\)'):
        ini.parameters('b21')


@pytest.mark.parametrize('text, warning', [
    ('[pluto] # the robot\na_b 1\n', None),
    ('[pluto]x\na_b 1\n', (1, 'text after [pluto] is ignored')),
    ('[pluto] trailing words\na_b 1\n', (1, 'text after [pluto] is ignored')),
    ('[*all]\na_b 1\n', (1, '[*all] is taken as [*], as CARMEN takes it')),
])
def test_headers_are_read_as_carmen_reads_them(tmp_path: pathlib.Path, text: str,
                                               warning: tuple[int, str] | None) -> None:
    path = tmp_path / 'h.ini'
    path.write_text(text)
    ini = read_ini(path)
    assert [(w.line, w.reason) for w in ini.warnings] == ([warning] if warning else [])
    robot = ini.robots()[0] if ini.robots() else None
    assert ini.parameters(robot)['a_b'].value == '1'


@pytest.mark.parametrize('argv, expected', [
    (['pd', '--robot=p2d8+', 'carmen.ini'], ['pd', '-R', 'p2d8+', 'carmen.ini']),
    (['pd', '-a', 'carmen.ini', '--robot', 'Pluto'], ['pd', '-R', 'Pluto', '-a', 'carmen.ini']),
    (['pd', '-R', 'x', '--ros-args', '--robot=y'], ['pd', '-R', 'x', '--ros-args', '--robot=y']),
    (['pd', '-a'], ['pd', '-a']),
])
def test_carmen_s_long_robot_option(argv: list[str], expected: list[str]) -> None:
    assert carmen_options(argv) == expected


@pytest.mark.parametrize('argv', [['pd', '--robot'], ['pd', '--robot=']])
def test_a_robot_option_without_a_robot_is_refused(argv: list[str]) -> None:
    with pytest.raises(ValueError, match='--robot needs a robot name'):
        carmen_options(argv)


def test_the_daemon_serves_the_quirks_with_robot_option(ros_domain: int,
                                                        quirks: pathlib.Path) -> None:
    """The real param_daemon, CARMEN's command line: ``param_daemon --robot=pluto carmen.ini``."""
    program = find_executable('wurde_mcp', 'param_daemon')
    with ChildProcess([program, '--robot=pluto', str(quirks)]) as child:
        child.expect('param_daemon ready', timeout=DEADLINE)
        user = ParameterTool('/param_daemon')
        try:
            names = user.names()
            assert {'robot.max_t_vel', 'robot.use_laser', 'robot.theta_gain', 'xsens.dev',
                    'camera.dev'} <= set(names)
            assert not {'xsens.adapt', 'robot.hidden', 'robot.stray', 'laser.front-dev'} & \
                set(names)
            assert user.get('robot.max_t_vel', 'robot.use_laser', 'robot.rectangular',
                            'robot.acceleration') == [0.3, False, 1, 0.7]
            assert user.describe('robot.theta_gain').description == \
                'carmen.ini robot_theta_gain (expert)'
            assert user.describe('robot.max_t_vel').description == 'carmen.ini robot_max_t_vel'
        finally:
            user.close()
        assert child.stop() == 0
    assert f'serves 7 parameters of [Pluto] from {quirks}' in child.stdout
    told = [line for line in child.stderr.splitlines() if line.startswith('param_daemon: warning:')]
    assert told == [f'param_daemon: warning: {quirks}:{line}: {reason}'
                    for line, reason in WARNINGS], child.stderr


@pytest.mark.parametrize('args, reason', [
    (['--robot=b21'], 'no robot [b21] (robots: Pluto, p2d8+, p2d8+dual)'),
    ([], '3 robots (Pluto, p2d8+, p2d8+dual): choose one with -R ROBOT or --robot=ROBOT'),
    (['--robot'], '--robot needs a robot name'),
])
def test_the_daemon_refuses_what_protects_it(ros_domain: int, quirks: pathlib.Path,
                                             args: list[str], reason: str) -> None:
    """A robot the file does not have, or none chosen among several, stops the daemon (exit 2)."""
    program = find_executable('wurde_mcp', 'param_daemon')
    with ChildProcess([program, str(quirks), *args]) as child:     # --robot last: no name follows
        assert child.process.wait(timeout=DEADLINE) == 2
        child.stop()
    assert reason in child.stderr, child.stderr
