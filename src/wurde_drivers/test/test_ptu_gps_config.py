"""ptu-config.xml and gps-config.xml: good files read, bad ones refused with file and line."""

from __future__ import annotations

import pathlib

import pytest

from wurde_drivers.errors import ConfigError
from wurde_drivers.gps import config as gps_config
from wurde_drivers.gps.config import GpsDevice, load_gps_config
from wurde_drivers.ptu import config as ptu_config
from wurde_drivers.ptu.config import PtuDevice, load_ptu_config

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config'

PTU_GOOD = """<?xml version="1.0"?>
<ptu-config>
  <!-- the camera's pan-tilt unit -->
  <device port="/dev/ttyS1" name="PTU"/>
  <device port="loop://" name="fast" baud="38400" rate="20"/>
</ptu-config>
"""

GPS_GOOD = """<?xml version="1.0"?>
<gps-config>
  <device port="/dev/ttyS3" name="PlutoGPS"/>
  <device port="/dev/ttyUSB1" name="rtk" baud="38400" origin-latitude="-33.8568"
          origin-longitude="151.2153" min-satellites="8" min-quality="4" timeout="1.5"/>
</gps-config>
"""


def write(tmp_path: pathlib.Path, name: str, text: str) -> pathlib.Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_good_ptu_file(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, 'ptu-config.xml', PTU_GOOD)
    plain, fast = load_ptu_config(path)
    assert plain == PtuDevice('/dev/ttyS1', 'PTU', 9600, 10.0, path=str(path), line=4)
    assert (fast.port, fast.baud, fast.rate, fast.line) == ('loop://', 38400, 20.0, 5)
    assert ptu_config.device_named([plain, fast], 'fast') is fast
    with pytest.raises(ConfigError, match=r'ptu-config\.xml: no <device> named "tilt" '
                                          r'\(devices: PTU, fast\)'):
        ptu_config.device_named([plain, fast], 'tilt')


def test_good_gps_file(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, 'gps-config.xml', GPS_GOOD)
    plain, rtk = load_gps_config(path)
    assert plain == GpsDevice('/dev/ttyS3', 'PlutoGPS', path=str(path), line=3)
    assert (plain.baud, plain.origin, plain.min_satellites, plain.min_quality, plain.timeout) == (
        4800, None, 6, 2, 3.0)                                   # Pluto 8.4's thresholds
    assert (rtk.baud, rtk.origin, rtk.min_satellites, rtk.min_quality, rtk.timeout) == (
        38400, (-33.8568, 151.2153), 8, 4, 1.5)
    assert rtk.line == 5          # libxml2: the line where a multi-line start tag ends
    assert gps_config.device_named([plain, rtk], 'rtk') is rtk
    with pytest.raises(ConfigError, match='cfg.xml'):
        gps_config.device_named([], 'rtk', path='cfg.xml')


def test_shipped_examples_read() -> None:
    (ptu,) = load_ptu_config(CONFIG / 'ptu' / 'ptu-config.xml')
    assert (ptu.name, ptu.port, ptu.baud, ptu.rate) == ('PTU', '/tmp/wurde-ptu', 9600, 10.0)
    (gps,) = load_gps_config(CONFIG / 'gps' / 'gps-config.xml')
    assert (gps.name, gps.port, gps.baud, gps.origin) == ('PlutoGPS', '/tmp/wurde-gps', 4800,
                                                          (59.3498, 18.0707))


@pytest.mark.parametrize(('body', 'line', 'reason'), [
    ('<ptu-config>\n  <device port="/dev/ttyS1"/>\n</ptu-config>', 2, 'needs attribute.*name'),
    ('<ptu-config>\n  <device port="p" name="a" speed="9600"/>\n</ptu-config>', 2,
     'unknown attribute.*speed'),
    ('<ptu-config>\n  <device port="p" name="a" baud="115200"/>\n</ptu-config>', 2,
     'baud="115200"'),
    ('<ptu-config>\n  <device port="p" name="a" rate="100"/>\n</ptu-config>', 2,
     'rate=100 of <device> is above 30'),
    ('<ptu-config>\n  <device port="p" name="a" rate="fast"/>\n</ptu-config>', 2,
     'rate="fast" of <device> is not a number'),
    ('<ptu-config>\n  <device port="" name="a"/>\n</ptu-config>', 2, 'port of <device> is empty'),
    ('<ptu-config>\n  <device port="p" name="a"/>\n\n  <device port="q" name="a"/>\n</ptu-config>',
     4, 'duplicate device name "a" \\(first on line 2\\)'),
    ('<ptu-config>\n  <ptu port="p" name="a"/>\n</ptu-config>', 2, 'unknown element <ptu>'),
    ('<ptu-config>\n  <device port="p" name="a">\n</ptu-config>', 3, 'not well-formed'),
    ('<ptu-config>\n</ptu-config>', 1, 'no <device>'),
    ('<gps-config>\n</gps-config>', 1, 'root element'),
])
def test_bad_ptu_file_names_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                          reason: str) -> None:
    path = write(tmp_path, 'ptu-config.xml', body)
    with pytest.raises(ConfigError, match=reason) as caught:
        load_ptu_config(path)
    assert str(caught.value).startswith(f'{path}:{line}: ')


@pytest.mark.parametrize(('body', 'line', 'reason'), [
    ('<gps-config>\n  <device name="g"/>\n</gps-config>', 2, 'needs attribute.*port'),
    ('<gps-config>\n  <device port="p" name="g" baud="19200"/>\n</gps-config>', 2,
     'baud="19200".*4800, 9600, 38400'),
    ('<gps-config>\n  <device port="p" name="g" origin-latitude="59.3"/>\n</gps-config>', 2,
     'both origin-latitude and origin-longitude'),
    ('<gps-config>\n  <device port="p" name="g" origin-longitude="18"/>\n</gps-config>', 2,
     'both origin-latitude and origin-longitude'),
    ('<gps-config>\n\n  <device port="p" name="g" origin-latitude="91" origin-longitude="0"/>\n'
     '</gps-config>', 3, 'origin-latitude=91 of <device> is above 90'),
    ('<gps-config>\n  <device port="p" name="g" origin-latitude="0" origin-longitude="east"/>\n'
     '</gps-config>', 2, 'origin-longitude="east" of <device> is not a number'),
    ('<gps-config>\n  <device port="p" name="g" origin-latitude="nan" origin-longitude="0"/>\n'
     '</gps-config>', 2, 'not finite'),
    ('<gps-config>\n  <device port="p" name="g" min-satellites="5.5"/>\n</gps-config>', 2,
     'min-satellites="5.5" of <device> is not an integer'),
    ('<gps-config>\n  <device port="p" name="g" min-quality="-1"/>\n</gps-config>', 2,
     'min-quality=-1 of <device> is below 0'),
    ('<gps-config>\n  <device port="p" name="g" min-quality="6"/>\n</gps-config>', 2,
     'min-quality=6 of <device> is no measured fix quality'),
    ('<gps-config>\n  <device port="p" name="g" timeout="0"/>\n</gps-config>', 2,
     'timeout=0.0 of <device> must be above 0 s'),
    ('<gps-config>\n  <device port="p" name="g" altitude="30"/>\n</gps-config>', 2,
     'unknown attribute.*altitude'),
    ('<gps-config>\n  <device port="p" name="g"/>\n  <device port="q" name="g"/>\n</gps-config>',
     3, 'duplicate device name "g" \\(first on line 2\\)'),
    ('<gps-config>\n  <receiver port="p" name="g"/>\n</gps-config>', 2,
     'unknown element <receiver>'),
    ('<gps-config>\n</gps-config>', 1, 'no <device>'),
    ('<!DOCTYPE gps-config [<!ENTITY x "y">]>\n<gps-config>\n</gps-config>', 1,
     'internal subset'),
])
def test_bad_gps_file_names_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                          reason: str) -> None:
    path = write(tmp_path, 'gps-config.xml', body)
    with pytest.raises(ConfigError, match=reason) as caught:
        load_gps_config(path)
    assert str(caught.value).startswith(f'{path}:{line}: ')
