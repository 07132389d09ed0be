"""dmu-config.xml and wrist-config.xml: the shipped files, defaults, and refusals with file:line."""

from __future__ import annotations

import pathlib

import pytest

from wurde_drivers.dmu.codec import DmuMode
from wurde_drivers.dmu.config import DmuDevice, load_dmu_config
from wurde_drivers.dmu.config import device_named as dmu_named
from wurde_drivers.errors import ConfigError
from wurde_drivers.wrist.config import WristDevice, load_wrist_config
from wurde_drivers.wrist.config import device_named as wrist_named

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config'


def write(tmp_path: pathlib.Path, name: str, text: str) -> pathlib.Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_shipped_dmu_config_names_the_emulators_link() -> None:
    [device] = load_dmu_config(CONFIG / 'dmu' / 'dmu-config.xml')
    assert (device.port, device.name, device.baud, device.mode, device.cutoff) == (
        '/tmp/wurde-dmu', 'PlutoDMU', 38400, DmuMode.ANGLE, 5.0)


def test_the_shipped_wrist_config_is_the_no_hardware_mode() -> None:
    [device] = load_wrist_config(CONFIG / 'wrist' / 'wrist-config.xml')
    assert (device.name, device.interface, device.channel, device.pan_id, device.tilt_id,
            device.emulate) == ('PlutoWrist', 'virtual', 'wrist', 1, 2, True)


def test_dmu_defaults_and_picking_by_name(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, 'dmu-config.xml', '<dmu-config>\n'
                 '  <device port="/dev/ttyS2" name="front"/>\n'
                 '  <device port="loop://" name="rear" baud="9600" mode="scaled" cutoff="2.5"/>\n'
                 '</dmu-config>\n')
    devices = load_dmu_config(path)
    assert dmu_named(devices, 'front') == DmuDevice('/dev/ttyS2', 'front', 38400, DmuMode.ANGLE, 5.0,
                                                    str(path), 2)
    assert dmu_named(devices, 'rear') == DmuDevice('loop://', 'rear', 9600, DmuMode.SCALED, 2.5,
                                                   str(path), 3)
    with pytest.raises(ConfigError, match=r'no <device> named "side" \(devices: front, rear\)') as info:
        dmu_named(devices, 'side')
    assert info.value.path == str(path)


@pytest.mark.parametrize(('device', 'line', 'reason'), [
    ('<device port="/dev/ttyS2"/>', 3, 'needs attribute'),
    ('<device port="/dev/ttyS2" name="d" baud="4800"/>', 3, 'baud="4800"'),
    ('<device port="/dev/ttyS2" name="d" mode="voltage"/>', 3, 'mode="voltage"'),
    ('<device port="/dev/ttyS2" name="d" cutoff="0"/>', 3, 'above 0 Hz'),
    ('<device port="/dev/ttyS2" name="d" cutoff="fast"/>', 3, 'not a number'),
    ('<device port="/dev/ttyS2" name="d" rate="100"/>', 3, 'unknown attribute'),
    ('<device port="/dev/ttyS2" name="d"/>\n<device port="x" name="d"/>', 4, 'duplicate device name'),
    ('<sensor port="/dev/ttyS2" name="d"/>', 3, 'unknown element <sensor>'),
])
def test_bad_dmu_configs_are_refused_with_file_and_line(tmp_path: pathlib.Path, device: str,
                                                         line: int, reason: str) -> None:
    path = write(tmp_path, 'dmu-config.xml',
                 f'<?xml version="1.0"?>\n<dmu-config>\n{device}\n</dmu-config>\n')
    with pytest.raises(ConfigError) as info:
        load_dmu_config(path)
    assert (info.value.path, info.value.line) == (str(path), line)
    assert reason in str(info.value) and str(info.value).startswith(f'{path}:{line}: ')


def test_an_empty_dmu_config_and_a_wrong_root_are_refused(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ConfigError, match='holds no <device>'):
        load_dmu_config(write(tmp_path, 'a.xml', '<dmu-config>\n</dmu-config>\n'))
    with pytest.raises(ConfigError, match='dmu-config'):
        load_dmu_config(write(tmp_path, 'b.xml', '<wrist-config/>\n'))


def test_wrist_defaults_and_picking_by_name(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, 'wrist-config.xml', '<wrist-config>\n'
                 '  <device name="w" interface="socketcan" channel="can0"/>\n'
                 '<device name="v" interface="virtual" channel="x" pan-id="7" tilt-id="0x8" emulate="1"/>\n'
                 '</wrist-config>\n')
    devices = load_wrist_config(path)
    assert wrist_named(devices, 'w') == WristDevice('w', 'socketcan', 'can0', 1, 2, False, str(path), 2)
    assert wrist_named(devices, 'v') == WristDevice('v', 'virtual', 'x', 7, 8, True, str(path), 3)
    with pytest.raises(ConfigError, match='no <device> named "PlutoWrist"'):
        wrist_named(devices, 'PlutoWrist')


@pytest.mark.parametrize(('device', 'reason'), [
    ('<device name="w" interface="socketcan" channel="can0" emulate="true"/>',
     'emulate="true" needs interface="virtual" (got "socketcan")'),
    ('<device name="w" interface="udp_multicast" channel="239.0.0.1" />', 'refused'),
    ('<device name="w" interface="canbus" channel="can0"/>', 'not a python-can interface'),
    ('<device name="w" interface="virtual" channel="x" pan-id="32"/>', 'above 31'),
    ('<device name="w" interface="virtual" channel="x" tilt-id="1"/>', 'both 1'),
    ('<device name="w" interface="virtual" channel="x" emulate="maybe"/>', 'not true or false'),
    ('<device name="w" interface="virtual"/>', 'channel'),
    ('<device name="w" interface="virtual" channel=""/>', 'empty'),
])
def test_bad_wrist_configs_are_refused_with_file_and_line(tmp_path: pathlib.Path, device: str,
                                                           reason: str) -> None:
    path = write(tmp_path, 'wrist-config.xml', f'<wrist-config>\n\n  {device}\n</wrist-config>\n')
    with pytest.raises(ConfigError) as info:
        load_wrist_config(path)
    assert str(info.value).startswith(f'{path}:3: ') and reason in str(info.value), str(info.value)
