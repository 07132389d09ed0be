"""rflex-config.xml (WURDE 7.6): good files, and bad ones refused with file:line and reason."""

from __future__ import annotations

import pathlib

import pytest

from wurde_drivers.errors import ConfigError
from wurde_drivers.rflex.config import RFlexDevice, device_named, load_rflex_config
from wurde_drivers.rflex.robots import ATRV_JR, B21R

EXAMPLE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'rflex' / 'rflex-config.xml'


def write(tmp_path: pathlib.Path, body: str) -> pathlib.Path:
    path = tmp_path / 'rflex-config.xml'
    path.write_text('<?xml version="1.0" encoding="UTF-8"?>\n' + body)
    return path


def test_the_shipped_example_loads() -> None:
    devices = load_rflex_config(EXAMPLE)
    base = device_named(devices, 'base')
    assert (base.type, base.robot, base.brake_reset) == ('B21r', B21R, True)
    assert device_named(devices, 'atrv').robot is ATRV_JR


def test_defaults_and_every_attribute(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, '<rflex-config>\n'
                 '  <device port="/dev/ttyS1" name="b21" type="B21r"/>\n'
                 '  <!-- a comment is fine -->\n'
                 '  <device port="loop://" name="jr" type="ATRVJr" brake-reset="true" '
                 'command-timeout="0.25"/>\n'
                 '</rflex-config>\n')
    devices = load_rflex_config(path)
    assert devices[0] == RFlexDevice('/dev/ttyS1', 'b21', 'B21r', False, 1.0, str(path), 3)
    assert (devices[1].brake_reset, devices[1].command_timeout, devices[1].line) == (True, 0.25, 5)


@pytest.mark.parametrize(('body', 'line', 'words'), [
    ('<rflex-config>\n  <device port="p" name="n"/>\n</rflex-config>', 3, 'type'),
    ('<rflex-config>\n  <device port="p" name="n" type="B14r"/>\n</rflex-config>', 3, 'B21r'),
    ('<rflex-config>\n  <device port="p" name="n" type="B21r" brake-reset="maybe"/>\n'
     '</rflex-config>', 3, 'true or false'),
    ('<rflex-config>\n  <device port="p" name="n" type="B21r" command-timeout="-1"/>\n'
     '</rflex-config>', 3, 'below'),
    ('<rflex-config>\n  <device port="p" name="n" type="B21r" command-timeout="soon"/>\n'
     '</rflex-config>', 3, 'not a number'),
    ('<rflex-config>\n  <device port="p" name="n" type="B21r" invert="true"/>\n'
     '</rflex-config>', 3, 'invert'),
    ('<rflex-config>\n  <laser port="p" name="n" type="B21r"/>\n</rflex-config>', 3, 'laser'),
    ('<rflex-config>\n  <device port="a" name="n" type="B21r"/>\n'
     '  <device port="b" name="n" type="ATRVJr"/>\n</rflex-config>', 4, 'duplicate device name "n" (first on line 3)'),
    ('<rflex-config>\n</rflex-config>', 2, 'no <device>'),
    ('<laser-config>\n</laser-config>', None, 'rflex-config'),
    ('<rflex-config>\n  <device port="p"\n</rflex-config>', None, ''),
])
def test_bad_files_name_file_line_and_reason(tmp_path: pathlib.Path, body: str,
                                             line: int | None, words: str) -> None:
    path = write(tmp_path, body)
    with pytest.raises(ConfigError) as caught:
        load_rflex_config(path)
    error = caught.value
    assert error.path == str(path)
    if line is not None:
        assert error.line == line
        assert f'{path}:{line}:' in str(error)
    assert words in str(error)


def test_missing_file_is_a_config_error(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ConfigError) as caught:
        load_rflex_config(tmp_path / 'nowhere.xml')
    assert 'nowhere.xml' in str(caught.value)


def test_device_named_refuses_an_unknown_name() -> None:
    devices = load_rflex_config(EXAMPLE)
    with pytest.raises(ConfigError) as caught:
        device_named(devices, 'lewis')
    assert str(EXAMPLE) in str(caught.value)
    assert '"lewis"' in str(caught.value) and 'base' in str(caught.value)
    with pytest.raises(ConfigError):
        device_named([], 'base')
