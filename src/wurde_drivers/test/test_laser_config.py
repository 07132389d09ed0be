"""laser-config.xml (WURDE guide 7.5): good files read, bad ones refused with file and line."""

from __future__ import annotations

import pathlib

import pytest

from wurde_drivers.errors import ConfigError
from wurde_drivers.sick.config import LaserDevice, device_named, load_laser_config

EXAMPLE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'sick' / 'laser-config.xml'

GOOD = """<?xml version="1.0"?>
<!DOCTYPE laser-config SYSTEM "laser-config.dtd">
<laser-config>
  <!-- the front laser -->
  <device port="/dev/ttyS0" name="front" type="LMS"/>
  <device port="/dev/ttyS1" name="back" type="PLS" invert="true" log="yes"/>
  <device port="/dev/ttyUSB0" name="fast" type="LMS" baud="500000" resolution="1.0"
          units="mm"/>
  <device port="/tmp/pty-rear" name="emulated" type="PLS" parity="none"/>
  <device port="/dev/ttyUSB1" name="odd" type="LMS" parity="even"/>
</laser-config>
"""


def write(tmp_path: pathlib.Path, text: str) -> pathlib.Path:
    path = tmp_path / 'laser-config.xml'
    path.write_text(text)
    return path


def test_good_file(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, GOOD)
    front, back, fast, emulated, odd = load_laser_config(path)
    assert front == LaserDevice('/dev/ttyS0', 'front', 'LMS', path=str(path), line=5)
    assert (front.baud, front.resolution, front.units, front.values) == (38400, 0.5, 'cm', 361)
    assert (back.type, back.invert, back.log) == ('PLS', True, True)
    # libxml2 gives a start tag spread over lines the line where the tag ends.
    assert (fast.baud, fast.values, fast.units, fast.line) == (500000, 181, 'mm', 8)
    assert device_named([front, back, fast], 'back') is back
    # parity: the type's own by default (PLS 8E1, LMS 8N1), else as configured
    assert [d.parity for d in (front, back, fast, emulated, odd)] == \
        ['none', 'even', 'none', 'none', 'even']
    assert LaserDevice('p', 'n', 'PLS').parity == 'even'
    assert LaserDevice('p', 'n', 'LMS').parity == 'none'


def test_missing_name_names_the_file(tmp_path: pathlib.Path) -> None:
    devices = load_laser_config(write(tmp_path, GOOD))
    with pytest.raises(ConfigError, match=r'laser-config\.xml: no <device> named "side"'):
        device_named(devices, 'side')
    with pytest.raises(ConfigError, match='cfg.xml'):
        device_named([], 'side', path='cfg.xml')


def test_shipped_example_reads() -> None:
    devices = load_laser_config(EXAMPLE)
    assert [device.name for device in devices] == ['laser', 'rearLaser']
    # the rear PLS is on sick_emulator's pty, which cannot carry parity
    assert [(device.type, device.parity) for device in devices] == [('LMS', 'none'),
                                                                    ('PLS', 'none')]


@pytest.mark.parametrize(('body', 'line', 'reason'), [
    ('<laser-config>\n  <device port="/dev/ttyS0" type="LMS"/>\n</laser-config>', 2,
     'needs attribute.*name'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS" speed="9600"/>\n</laser-config>', 2,
     'unknown attribute.*speed'),
    ('<laser-config>\n  <device port="p" name="a" type="LMX"/>\n</laser-config>', 2,
     'type="LMX".*PLS, LMS'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS" invert="maybe"/>\n</laser-config>',
     2, 'invert="maybe"'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS" baud="4800"/>\n</laser-config>', 2,
     'baud="4800"'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS" resolution="0.25"/>\n'
     '</laser-config>', 2, 'resolution="0.25"'),
    ('<laser-config>\n  <device port="p" name="a" type="PLS" units="mm"/>\n</laser-config>', 2,
     'PLS'),
    ('<laser-config>\n  <device port="p" name="a" type="PLS" parity="odd"/>\n</laser-config>', 2,
     'parity="odd".*none, even'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS"\n          parity=""/>\n'
     '</laser-config>', 3, 'parity of <device> is empty'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS"/>\n'
     '  <device port="q" name="a" type="PLS"/>\n</laser-config>', 3,
     'duplicate device name "a" \\(first on line 2\\)'),
    ('<laser-config>\n  <laser port="p" name="a" type="LMS"/>\n</laser-config>', 2,
     'unknown element <laser>'),
    ('<laser-config>\n  <device port="p" name="a" type="LMS">\n</laser-config>', 3,
     'not well-formed'),
    ('<laser-config>\n</laser-config>', 1, 'no <device>'),
    ('<rflex-config>\n</rflex-config>', 1, 'root element'),
])
def test_bad_files_are_refused_with_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                                  reason: str) -> None:
    path = write(tmp_path, body)
    with pytest.raises(ConfigError, match=reason) as caught:
        load_laser_config(path)
    assert caught.value.path == str(path)
    assert caught.value.line == line
    assert str(caught.value).startswith(f'{path}:{line}: ')
