"""joystick-config.xml (guide 10.1.6): the shipped files are read as the appendix means them, bad
files are refused with file, line and reason; the emulator's command lines likewise."""

from __future__ import annotations

import pathlib

import pytest
from wurde_drivers.errors import ConfigError
from wurde_drivers.joystick.config import JoystickLayout, layout_named, load_joystick_config
from wurde_drivers.joystick.script import Command, ScriptError, parse_command

ROOT = pathlib.Path(__file__).resolve().parents[3]
APPENDIX_AXES = {'rotate': 0, 'translate': 1, 'quicktilt': 2, 'quickpan': 3, 'pan': 4, 'tilt': 5}
APPENDIX_BUTTONS = {'sound1': 0, 'sound2': 1, 'sound3': 2, 'sound4': 3, 'sound5': 8, 'sound6': 9,
                    'stop': 4, 'quit': 5}


def test_the_shipped_configs_are_the_appendix_file() -> None:
    (guide,) = load_joystick_config(ROOT / 'config' / 'guide-ch1' / 'joystick-config.xml')
    assert guide.name == 'Saitek P990 Dual Analog Pad'
    assert guide.axes == APPENDIX_AXES and guide.buttons == APPENDIX_BUTTONS
    (sim,) = load_joystick_config(ROOT / 'config' / 'blind-teleop' / 'joystick-config.xml')
    assert sim.axes == APPENDIX_AXES
    assert sim.buttons == {**APPENDIX_BUTTONS, 'resetPTU': 6}


def _write(tmp_path: pathlib.Path, body: str) -> pathlib.Path:
    path = tmp_path / 'joystick-config.xml'
    path.write_text('<?xml version="1.0"?>\n<joystick-config>\n' + body + '</joystick-config>\n')
    return path


@pytest.mark.parametrize('body, line, reason', [
    ('<joystick name="J">\n<axis id="b5" name="tilt"/>\n</joystick>\n', 4, 'is not an integer'),
    ('<joystick name="J">\n<axis id="256" name="tilt"/>\n</joystick>\n', 4, 'above 255'),
    ('<joystick name="J">\n<axis id="1" name="a"/>\n<axis id="1" name="b"/>\n</joystick>\n', 5,
     'axis id "1" given twice (first on line 4)'),
    ('<joystick name="J">\n<button id="1" name="a"/>\n<button id="2" name="a"/>\n</joystick>\n', 5,
     'button name "a" given twice'),
    ('<joystick name="J">\n<axis id="1" nme="a"/>\n</joystick>\n', 4, 'unknown attribute(s) nme'),
    ('<joystick name="J">\n<hat id="1" name="a"/>\n</joystick>\n', 4, 'unknown element <hat>'),
    ('<joystick name="J">\n</joystick>\n', 3, 'names no axis and no button'),
    ('<joystick>\n<axis id="1" name="a"/>\n</joystick>\n', 3, 'needs attribute(s) name'),
    ('<joystick name="J"><axis id="1" name="a"/></joystick>\n'
     '<joystick name="J"><axis id="1" name="a"/></joystick>\n', 4, 'duplicate joystick name "J"'),
    ('', 2, 'holds no <joystick>'),
    ('<joystick name="J">\n<axis id="1" name="a">\n</joystick>\n', None, ''),   # not well formed
])
def test_bad_configs_are_refused_with_file_line_and_reason(tmp_path: pathlib.Path, body: str,
                                                           line: int | None, reason: str) -> None:
    path = _write(tmp_path, body)
    with pytest.raises(ConfigError) as caught:
        load_joystick_config(path)
    text = str(caught.value)
    assert text.startswith(f'{path}:'), text
    if line is not None:
        assert text.startswith(f'{path}:{line}:') and reason in text, text


def test_a_layout_is_picked_by_name() -> None:
    layouts = [JoystickLayout('A', {'x': 0}, {}, 'f.xml', 3), JoystickLayout('B', {'y': 1}, {}, 'f.xml', 7)]
    assert layout_named(layouts).name == 'A'
    assert layout_named(layouts, 'B').axes == {'y': 1}
    with pytest.raises(ConfigError, match='no <joystick> named "C"'):
        layout_named(layouts, 'C')


def test_emulator_commands() -> None:
    layout = JoystickLayout('J', {'translate': 1}, {'quit': 5})
    assert parse_command('  # only a comment', layout) is None
    assert parse_command('axis translate -16000  # forward', layout) == Command('axis', 1, -16000)
    assert parse_command('axis 7 32767', layout) == Command('axis', 7, 32767)
    assert parse_command('press quit', layout) == Command('button', 5, 1)
    assert parse_command('button 3 0', layout) == Command('button', 3, 0)
    assert parse_command('wait 0.5', layout) == Command('wait', value=0.5)
    assert parse_command('wait-reader', layout) == Command('wait-reader')
    for bad, reason in [('axis rudder 1', 'no axis named "rudder"'), ('axis 1 40000', 'not within'),
                        ('button quit 2', r'not 0 \(released\) or 1'), ('jump', 'unknown command'),
                        ('press', 'takes 1 argument'), ('wait soon', 'not a number')]:
        with pytest.raises(ScriptError, match=reason):
            parse_command(bad, layout)
