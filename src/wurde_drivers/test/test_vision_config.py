"""The VisionModule's two config files (guide 7.2.1, 7.2.2): the appendix's examples as shipped
in config/vision are accepted; bad files are refused with file, line and reason."""

from __future__ import annotations

import pathlib

import pytest
from wurde_idl.errors import ConfigError

from wurde_drivers.vision.camera_config import FIREWIRE_CONTROLS, load_camera_config
from wurde_drivers.vision.operators.image_writer import ImageWriter
from wurde_drivers.vision.playback import PlaybackCamera
from wurde_drivers.vision.registry import load_plugins, operator_class
from wurde_drivers.vision.runner import load_layout
from wurde_drivers.vision.vision_config import load_vision_config

SHIPPED = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'vision'


def test_shipped_camera_config_is_accepted() -> None:
    cameras = load_camera_config(SHIPPED / 'camera-config.xml')
    assert list(cameras) == ['rightCamera', 'leftCamera', 'DesktopPlayback']
    right = cameras['rightCamera']
    assert right.type == 'firewire' and right.options['id'] == '0x8004602000301fc'
    assert all(right.options[name] for name in (*FIREWIRE_CONTROLS, 'autoiris'))
    assert right.options['brightness'] == '1024' and right.options['autoiris'] == 'true'
    playback = cameras['DesktopPlayback']
    assert playback.type == 'playback'
    assert (playback.text('imageSuffix'), playback.text('imagePrefix'), playback.text('imageDevice')) == \
        ('.ppm', 'faceTest', 'main')
    assert playback.path_option('imageDirectory') == str(SHIPPED / 'faceSet')


def test_shipped_vision_config_is_accepted() -> None:
    vision = load_vision_config(SHIPPED / 'vision-config.xml')
    assert list(vision.modules) == ['LeftVisionModule', 'RightVisionModule', 'DesktopVisionModule']
    left = vision.module('LeftVisionModule')
    assert left.comment == 'Module for the left camera only' and left.cameras == ('leftCamera',)
    # The camera as an attribute (LeftWriter) and as a child entity (DesktopWriter).
    assert [(o.name, o.type, o.cameras) for o in left.operators] == \
        [('LeftWriter', 'ImageWriter', ('leftCamera',))]
    desk = vision.module('DesktopVisionModule').operators[0]
    assert (desk.name, desk.type, desk.cameras) == ('DesktopWriter', 'ImageWriter', ('DesktopPlayback',))
    assert [p.path for p in vision.plugins] == [str(SHIPPED / 'lib' / f'lib{n}.so') for n in
                                                ('ImageWriter', 'ImagePublisher', 'DataCollector',
                                                 'StereoDataCollector')]
    notes: list[str] = []
    assert load_plugins(vision.plugins, notes.append) == {}     # C++ libraries: skipped, said so
    assert len(notes) == 4 and 'not loaded' in notes[0]


def test_shipped_layouts_build() -> None:
    """Every layout of the shipped files builds its cameras and operators (no I/O yet)."""
    layout, cameras, operators = load_layout(str(SHIPPED / 'camera-config.xml'),
                                             str(SHIPPED / 'vision-config.xml'),
                                             'DesktopVisionModule', lambda _: None)
    assert layout.name == 'DesktopVisionModule'
    assert [type(c) for c in cameras] == [PlaybackCamera] and [type(o) for o in operators] == [ImageWriter]
    for name in ('LeftVisionModule', 'RightVisionModule'):
        _, cameras, _ = load_layout(str(SHIPPED / 'camera-config.xml'),
                                    str(SHIPPED / 'vision-config.xml'), name, lambda _: None)
        assert cameras[0].type_name == 'firewire'
    for name, operator in (('SimVision', 'ImageWriter'), ('SimCollector', 'StereoDataCollector')):
        _, cameras, operators = load_layout(str(SHIPPED / 'sim-camera-config.xml'),
                                            str(SHIPPED / 'sim-vision-config.xml'), name, lambda _: None)
        assert cameras[0].type_name == 'sim' and type(operators[-1]).__name__ == operator


CAMERA_CASES = [
    ('<camera name="a" type="usb"/>', 3, 'must be one of firewire, playback, sim'),
    ('<camera name="a" type="firewire"/>', 3, 'needs option(s) id'),
    ('<camera name="a" type="playback">\n<option name="imageDir" value="x"/>\n</camera>', 4,
     'has no option "imageDir"'),
    ('<camera name="a" type="playback">\n<option name="imageDirectory" value="x"/>\n'
     '<option name="imageDirectory" value="y"/>\n</camera>', 5, 'given twice'),
    ('<camera name="a" type="playback"><option name="imageDirectory" value="x"/></camera>\n'
     '<camera name="a" type="sim"/>', 4, 'duplicate camera name "a"'),
    ('<camera name="a" type="sim" colour="red"/>', 3, 'unknown attribute(s) colour'),
    ('<camera name="a" type="firewire">\n<option name="id" value="0"/>\n'
     '<option name="gain" value="high"/>\n</camera>', 5, 'option gain="high" of camera "a" is not an integer'),
    ('<camera name="a" type="firewire">\n<option name="id" value="0"/>\n'
     '<option name="autoiris" value="maybe"/>\n</camera>', 5, 'is not true or false'),
    ('<camera name="a" type="sim">\n<option name="maxRange" value="inf"/>\n</camera>', 4,
     'option maxRange="inf" of camera "a" is not finite'),
    ('<lens name="a"/>', 3, 'unknown element <lens>'),
    ('', 2, 'holds no <camera>'),
]


@pytest.mark.parametrize(('body', 'line', 'reason'), CAMERA_CASES)
def test_bad_camera_config_is_refused_with_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                                         reason: str) -> None:
    path = tmp_path / 'camera-config.xml'
    path.write_text(f'<?xml version="1.0"?>\n<camera-config>\n{body}\n</camera-config>\n')
    with pytest.raises(ConfigError) as caught:
        load_camera_config(path)
    assert str(caught.value).startswith(f'{path}:{line}:'), str(caught.value)
    assert reason in str(caught.value)


VISION_CASES = [
    ('<module name="m">\n<camera name="c"/>\n</module>', 3, 'needs at least one <camera> and one <operator>'),
    ('<module name="m">\n<camera name="c"/>\n<operator name="o" type="ImageWriter"/>\n</module>', 5,
     'needs one or two cameras, has 0'),
    ('<module name="m">\n<camera name="c"/>\n<operator name="o" type="ImageWriter" camera="d"/>\n</module>',
     5, 'uses camera "d", which its module does not open'),
    ('<module name="m">\n<camera name="c"/><camera name="d"/><camera name="e"/>\n'
     '<operator name="o" type="T" camera="c">\n<camera name="d"/><camera name="e"/>\n</operator>\n</module>',
     5, 'needs one or two cameras, has 3'),
    ('<module name="m">\n<camera name="c"/>\n<operator name="o" type="T" camera="c"/>\n'
     '<operator name="o" type="U" camera="c"/>\n</module>', 6, 'duplicate operator name "o"'),
    ('<module name="m">\n<camera name="c"/>\n<operator name="o" type="T" camera="c">\n'
     '<option name="x"/>\n</operator>\n</module>', 6, 'needs attribute(s) value'),
    ('<module name="m"><camera name="c"/><operator name="o" type="T" camera="c"/></module>\n'
     '<module name="m"><camera name="c"/><operator name="o" type="T" camera="c"/></module>', 4,
     'duplicate module name "m"'),
    ('<plugin/>', 3, 'needs attribute(s) path'),
    ('<layout name="m"/>', 3, 'unknown element <layout>'),
]


@pytest.mark.parametrize(('body', 'line', 'reason'), VISION_CASES)
def test_bad_vision_config_is_refused_with_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                                         reason: str) -> None:
    path = tmp_path / 'vision-config.xml'
    path.write_text(f'<?xml version="1.0"?>\n<vision-config>\n{body}\n</vision-config>\n')
    with pytest.raises(ConfigError) as caught:
        load_vision_config(path)
    assert str(caught.value).startswith(f'{path}:{line}:'), str(caught.value)
    assert reason in str(caught.value)


def _vision(tmp_path: pathlib.Path, operator: str, plugin: str = '') -> pathlib.Path:
    path = tmp_path / 'vision-config.xml'
    path.write_text('<?xml version="1.0"?>\n<vision-config>\n<module name="m">\n<camera name="c"/>\n'
                    f'{operator}\n</module>\n{plugin}\n</vision-config>\n')
    return path


def test_operator_types_and_options_are_checked_with_the_line(tmp_path: pathlib.Path) -> None:
    path = _vision(tmp_path, '<operator name="o" type="ImageWritter" camera="c"/>')
    with pytest.raises(ConfigError, match=r':5: operator "o": unknown operator type "ImageWritter" '
                                          r'\(known: .*ImageWriter'):
        operator_class(load_vision_config(path).module('m').operators[0], {})
    path = _vision(tmp_path, '<operator name="o" type="ImageWriter" camera="c">'
                             '<option name="dir" value="x"/></operator>')
    spec = load_vision_config(path).module('m').operators[0]
    with pytest.raises(ConfigError, match=r':5: operator "o": ImageWriter has no option\(s\) dir'):
        operator_class(spec, {})(spec)
    path = _vision(tmp_path, '<operator name="o" type="ImagePublisher" camera="c">'
                             '<option name="format" value="bgr"/></operator>')
    spec = load_vision_config(path).module('m').operators[0]
    with pytest.raises(ConfigError,
                       match=r':5: operator "o": format "bgr" is not one of gray, rgb, yuv24, yuv422'):
        operator_class(spec, {})(spec)
    with pytest.raises(ConfigError, match=r'no <module name="x"> \(modules: m\); use -n'):
        load_vision_config(path).module('x')


def test_a_python_plugin_supplies_operators(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'my_ops.py').write_text(
        'from wurde_drivers.vision.operator import Operator\n\n'
        'class Counter(Operator):\n    OPTIONS = {"every": "10"}\n')
    path = _vision(tmp_path, '<operator name="o" type="Counter" camera="c"/>', '<plugin path="my_ops.py"/>')
    vision = load_vision_config(path)
    plugins = load_plugins(vision.plugins, lambda _: None)
    operator = operator_class(vision.module('m').operators[0], plugins)(vision.module('m').operators[0])
    assert type(operator).__name__ == 'Counter' and operator.options == {'every': '10'}
    bad = _vision(tmp_path, '<operator name="o" type="Counter" camera="c"/>', '<plugin path="no_such.module"/>')
    with pytest.raises(ConfigError, match=r':7: plugin no_such.module cannot be imported'):
        load_plugins(load_vision_config(bad).plugins, lambda _: None)


@pytest.mark.parametrize('mode', [0o664, 0o646])
def test_a_plugin_file_others_may_write_is_refused_before_it_runs(tmp_path: pathlib.Path, mode: int) -> None:
    ran = tmp_path / 'ran'
    plugin = tmp_path / 'my_ops.py'
    plugin.write_text(f'open({str(ran)!r}, "w").close()\n')
    plugin.chmod(mode)
    path = _vision(tmp_path, '<operator name="o" type="Counter" camera="c"/>', '<plugin path="my_ops.py"/>')
    with pytest.raises(ConfigError, match=r':7: plugin .*my_ops.py is writable by others than its owner'):
        load_plugins(load_vision_config(path).plugins, lambda _: None)
    assert not ran.exists()
    plugin.chmod(0o644)
    load_plugins(load_vision_config(path).plugins, lambda _: None)
    assert ran.exists()
