"""carmen.ini: sections, the robot override, and every refusal naming file and line."""

from __future__ import annotations

import pathlib

import pytest
from wurde_idl.errors import ConfigError

from wurde_mcp.carmen import choose_robot, find_ini, read_ini, robots
from wurde_mcp.carmen.daemon import split_arguments

SHIPPED = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'carmen' / 'carmen.ini'

INI = """\
# a comment line
[*]
robot_max_t_vel   0.5      # trailing comment
robot_name        Pluto the robot
laser_flipped     off

[pluto]
robot_max_t_vel   0.3
navigator_approach_dist 0.2

[atrv]
robot_max_t_vel   1
"""


def write(tmp_path: pathlib.Path, text: str | bytes, name: str = 'carmen.ini') -> pathlib.Path:
    path = tmp_path / name
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return path


def test_sections_values_and_the_robot_override(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, INI)
    ini = read_ini(path)
    assert ini.robots() == ['pluto', 'atrv'] == robots(path)
    common = ini.parameters(None)
    assert {n: e.value for n, e in common.items()} == {
        'laser_flipped': 'off', 'robot_max_t_vel': '0.5', 'robot_name': 'Pluto the robot'}
    pluto = ini.parameters('pluto')
    assert list(pluto) == sorted(pluto)
    assert pluto['robot_max_t_vel'].value == '0.3' and pluto['robot_max_t_vel'].line == 8
    assert pluto['robot_name'].value == 'Pluto the robot'
    assert (pluto['navigator_approach_dist'].module,
            pluto['navigator_approach_dist'].variable) == ('navigator', 'approach_dist')
    assert 'navigator_approach_dist' not in ini.parameters('atrv')
    assert ini.parameters('atrv')['robot_max_t_vel'].value == '1'


def test_choosing_the_robot(tmp_path: pathlib.Path) -> None:
    ini = read_ini(write(tmp_path, INI))
    assert choose_robot(ini, 'atrv') == 'atrv'
    with pytest.raises(ConfigError, match=r'2 robots \(pluto, atrv\): choose one with -R ROBOT or '
                                          r'--robot=ROBOT'):
        choose_robot(ini, None)
    with pytest.raises(ConfigError, match=r'no robot \[b21\] \(robots: pluto, atrv\)'):
        choose_robot(ini, 'b21')
    one = read_ini(write(tmp_path, '[*]\na_b 1\n[pluto]\na_b 2\n', 'one.ini'))
    assert choose_robot(one, None) == 'pluto'
    common = read_ini(write(tmp_path, '[*]\na_b 1\n', 'common.ini'))
    assert choose_robot(common, None) is None and common.parameters(None)['a_b'].value == '1'


def test_the_shipped_ini_serves_pluto() -> None:
    ini = read_ini(SHIPPED)
    assert choose_robot(ini, None) == 'pluto'
    pluto = ini.parameters('pluto')
    assert pluto['robot_max_t_vel'].value == '0.3' and pluto['laser_flipped'].value == 'on'
    assert pluto['avoid_safety_distance'].value == '0.3'


@pytest.mark.parametrize('text, line, reason', [
    ('robot_max_t_vel 0.5\n[*]\n', 1, "'robot_max_t_vel' is before the first section header"),
    ('[*]\n\nrobot_max_t_vel\n', 3, 'robot_max_t_vel has no value: skipped'),
    ('[*]\nrobot_max_t_vel   # only a comment\n', 2, 'has no value'),
    ('# c\n[pluto\n', 2, "section header '[pluto' is not [*], [expert] or [robot]: the lines "
                        'under it are skipped'),
    ('[two words]\n', 1, 'is not [*], [expert] or [robot]'),
    ('[]\n', 1, 'is not [*], [expert] or [robot]'),
    ('[*]\nmaxspeed 1\n', 2, "'maxspeed' is not module_variable"),
    ('[*]\n_speed 1\n', 2, 'is not module_variable'),
    ('[*]\nrobot_ 1\n', 2, 'is not module_variable'),
    ('[*]\n$include other.ini\n', 2, "'$include' is not module_variable"),
    ('[*]\nrobot_max-vel 1\n', 2, 'characters other than letters, digits and _'),
    ('[*]\na_b 1\n[p]\na_b 2\n[*]\nc_d 3\na_b 4\n', 7, 'a_b is set again in [*] (first on line '
                                                      '2): this later value wins'),
])
def test_every_warning_names_file_line_and_reason(tmp_path: pathlib.Path, text: str, line: int,
                                                  reason: str) -> None:
    """What CARMEN's daemon skips or reads on is warned about, with file:line; nothing raises."""
    path = write(tmp_path, text)
    warnings = read_ini(path).warnings
    assert [(w.path, w.line) for w in warnings if reason in w.reason] == [(str(path), line)], \
        warnings
    assert any(str(w).startswith(f'{path}:{line}: ') for w in warnings)


def test_non_utf8_is_refused_with_its_line(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, b'[*]\nrobot_name ok\nrobot_owner M\xfcller\n')
    with pytest.raises(ConfigError, match=r':3: not UTF-8 \(byte 0xfc\)'):
        read_ini(path)


def test_a_missing_file_is_a_config_error(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ConfigError, match='cannot read'):
        read_ini(tmp_path / 'nope.ini')


def test_search_order(tmp_path: pathlib.Path) -> None:
    work = tmp_path / 'bin'
    work.mkdir()
    with pytest.raises(ConfigError, match=r'carmen.ini, ../carmen.ini, ../src/carmen.ini'):
        find_ini(work)
    (tmp_path / 'src').mkdir()
    write(tmp_path / 'src', '[*]\n')
    assert find_ini(work) == str(tmp_path / 'src' / 'carmen.ini')
    write(tmp_path, '[*]\n')
    assert find_ini(work) == str(tmp_path / 'carmen.ini')
    write(work, '[*]\n')
    assert find_ini(work) == str(work / 'carmen.ini')


def test_daemon_arguments() -> None:
    assert split_arguments([]) == (None, None)
    assert split_arguments(['office.yaml']) == ('office.yaml', None)
    assert split_arguments(['my.ini']) == (None, 'my.ini')
    assert split_arguments(['office.yaml', 'my.ini']) == ('office.yaml', 'my.ini')
    with pytest.raises(ValueError):
        split_arguments(['a', 'b', 'c'])
