"""The base types beyond WURDE 7.6's two: the guide appendix's ``B21ir`` (10.1.5), loaded as printed,
and Pluto's own ATRV2 (Pluto 2), in rflex-config and in the dummy base's sim-config."""

from __future__ import annotations

import math
import os
import pathlib
import textwrap

import pytest
from sim_fixture import Observer, sim_config
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.errors import ConfigError
from wurde_drivers.rflex.config import load_rflex_config
from wurde_drivers.rflex.module import limits_for
from wurde_drivers.rflex.robots import ATRV2, ATRV_JR, B21IR, B21R, DriveKind
from wurde_drivers.sim.config import load_sim_config
from wurde_testing.manual import example

#: Guide 10.1.5 as printed; only the XML declaration's OCR glyphs (``<?7xml ... 7>``) are undone.
APPENDIX = '''<?xml version="1.0" encoding="UTF-8" ?>

<!DOCTYPE rflex-config SYSTEM "rflex-config.dtd">
<rflex-config>

<device port="/dev/ttyRO" name="TomRFlex" type="B21ir"/>
</rflex-config>
'''


def test_the_appendix_rflex_config_loads_as_a_b21r(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'rflex-config.xml'
    path.write_text(APPENDIX)
    (device,) = load_rflex_config(path)
    assert (device.port, device.name, device.type, device.line) == ('/dev/ttyRO', 'TomRFlex', 'B21ir', 6)
    robot = device.robot
    assert robot is B21IR and robot.drive is DriveKind.SYNCHRO
    assert (robot.units_per_m, robot.units_per_rad, robot.sonars, robot.bumpers) == \
        (B21R.units_per_m, B21R.units_per_rad, B21R.sonars, B21R.bumpers)
    assert limits_for(robot).wheel_base == limits_for(B21R).wheel_base


def test_the_readme_example_loads(tmp_path: pathlib.Path) -> None:
    block = example('rflex_types', 'xml')
    path = tmp_path / 'rflex-config.xml'
    path.write_text(textwrap.dedent(block))
    pluto, tom = load_rflex_config(path)
    assert (pluto.name, pluto.robot, pluto.brake_reset) == ('PlutoBase', ATRV2, True)
    assert (tom.name, tom.robot) == ('TomRFlex', B21IR)


def test_atrv2_is_skid_steered_and_an_unknown_type_names_the_known_ones(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'rflex-config.xml'
    path.write_text('<?xml version="1.0"?>\n<rflex-config>\n  <device port="/dev/ttyS0" name="pluto" type="ATRV2"/>\n'
                    '</rflex-config>\n')
    (device,) = load_rflex_config(path)
    assert device.robot is ATRV2 and ATRV2.drive is DriveKind.DIFFERENTIAL
    assert (ATRV2.units_per_m, ATRV2.sonars) == (ATRV_JR.units_per_m, ATRV_JR.sonars)
    assert limits_for(ATRV2).wheel_base > limits_for(ATRV_JR).wheel_base       # the bigger body
    path.write_text('<?xml version="1.0"?>\n<rflex-config>\n  <device port="p" name="n" type="ATRV3"/>\n'
                    '</rflex-config>\n')
    with pytest.raises(ConfigError) as caught:
        load_rflex_config(path)
    assert f'{path}:3:' in str(caught.value)
    assert all(name in str(caught.value) for name in ('B21r', 'B21ir', 'ATRVJr', 'ATRV2'))


@pytest.mark.parametrize(('kind', 'synchro', 'radius'), [
    ('ATRV2', False, round(math.hypot(1.05, 0.65) / 2, 2)), ('B21ir', True, 0.35),
    ('B21r', True, 0.35), ('ATRVJr', False, 0.35)])
def test_the_sim_base_types_and_their_default_radius(tmp_path: pathlib.Path, kind: str, synchro: bool,
                                                     radius: float) -> None:
    path = sim_config(tmp_path, elements={'base': {'type': kind}})
    text = path.read_text().replace(' radius="0.35"', '')        # the type's own default
    assert text != path.read_text()
    path.write_text(text)
    config = load_sim_config(path)
    assert (config.base.type, config.base.synchro, config.robot.bumpers.radius) == (kind, synchro, radius)


def test_a_sim_base_of_another_type_is_refused_with_its_line(tmp_path: pathlib.Path) -> None:
    path = sim_config(tmp_path, elements={'base': {'type': 'Magellan'}})
    line = next(i for i, text in enumerate(path.read_text().splitlines(), 1) if '<base' in text)
    with pytest.raises(ConfigError) as caught:
        load_sim_config(path)
    assert f'{path}:{line}:' in str(caught.value) and 'ATRV2' in str(caught.value)


def test_the_dummy_atrv2_supplies_a_robot_drive_and_its_body(ros_domain: int, tmp_path: pathlib.Path) -> None:
    path = sim_config(tmp_path, elements={'base': {'type': 'ATRV2'}})
    path.write_text(path.read_text().replace(' radius="0.35"', ''))
    observer = Observer({'PlutoBaseDrive': 'RobotDrive', 'PlutoBaseBumpers': 'Bumper'})
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    try:
        with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-n', 'PlutoBase'], env=env):
            observer.until(lambda o: 'PlutoBaseDrive' in o.infos and 'PlutoBaseBumpers' in o.infos,
                           'the RobotDrive and bumper infos', timeout=60)
            front = observer.infos['PlutoBaseBumpers'].sensor_positions[0]
            assert front.x == pytest.approx(0.62)
    finally:
        observer.close()
