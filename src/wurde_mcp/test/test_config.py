"""MCP configuration and mappings: both seed forms, and refusals with file, line and reason."""

from __future__ import annotations

import pathlib

import pytest

from wurde_core import ConfigError, ProcessLocale, ProcessType
from wurde_core.cooperative import QUANTUM_S
from wurde_idl import load_all
from wurde_testing.manual import example
from wurde_mcp.config import McpConfig, read_mcp_config, read_mcp_mappings, validate

ROOT = pathlib.Path(__file__).resolve().parents[3]

CHAPTER1 = '''<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE mcp-config SYSTEM "mcp-config.dtd">
<mcp-config>
<module name="VectorMover">
<binary>vectorMover</binary>
</module>
<module name="HollowayLMS">
<binary>sickServer</binary>
<options>-n HollowayLMS</options>
</module>
</mcp-config>
'''

APPENDIX = '''<?xml version="1.0" encoding="UTF-8"?>
<robot>
<wurde-config xmlns="http://wurde.sf.net/wurde-config"><data-directory location="/d"/></wurde-config>
<mcp-config xmlns:xs="http://www.w3.org/2001/XMLSchema-instance"
xmlns="http://wurde.sf.net/mcp-config"
xs:schemalocation="http://wurde.sf.net/mcp-config mcp.xsd">
<module name="TomRFlex" binary="rFlexServer"/>
<module name="SynchroMover" binary="synchroMover">
<connect consumer="DriveClient" supplier="TomRFlexDrive" interface="RobotDrive"/>
<connect consumer="EgoClient" supplier="TomRFlexMotion" interface="Egomotion"/>
</module>
<module name="BlindTeleop">
<connect consumer="EgoClient" supplier="TomRFlexMotion" interface="Egomotion"/>
</module>
<module name="StereoVisionModule" binary="visionModule" managed="critical">
<arg value="-n StereoVisionModule"/>
<arg value="-v local-vision-config.xml"/>
</module>
</mcp-config>
</robot>
'''


def write(tmp_path: pathlib.Path, text: str, name: str = 'mcp.xml') -> pathlib.Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_chapter1_form(tmp_path: pathlib.Path) -> None:
    config = read_mcp_config(write(tmp_path, CHAPTER1))
    assert list(config.modules) == ['VectorMover', 'HollowayLMS']
    lms = config.modules['HollowayLMS']
    assert (lms.binary, lms.args, lms.locale, lms.managed) == \
        ('sickServer', ['-n', 'HollowayLMS'], ProcessLocale.INTERNAL, ProcessType.MANAGED)


def test_appendix_combined_form(tmp_path: pathlib.Path) -> None:
    config = read_mcp_config(write(tmp_path, APPENDIX))
    assert config.modules['StereoVisionModule'].args == \
        ['-n', 'StereoVisionModule', '-v', 'local-vision-config.xml']
    assert config.modules['StereoVisionModule'].managed == ProcessType.CRITICAL
    assert config.modules['BlindTeleop'].locale == ProcessLocale.EXTERNAL  # no binary
    assert [(m.interface, m.source, m.object) for m in config.mappings_for('SynchroMover')] == \
        [('RobotDrive', 'TomRFlexDrive', 'DriveClient'),
         ('Egomotion', 'TomRFlexMotion', 'EgoClient')]
    validate(config, load_all())


@pytest.mark.parametrize('name', ['foo', 'blind-teleop', 'guide-ch1'])
def test_shipped_configs_load(name: str) -> None:
    config = read_mcp_config(ROOT / 'config' / name / 'mcp-config.xml')
    read_mcp_mappings(ROOT / 'config' / name / 'mcp-mappings.xml', config)
    validate(config, load_all())
    assert config.mappings


@pytest.mark.parametrize('text, line, reason', [
    ('<mcp-config>\n<modul name="a"/>\n</mcp-config>', 2, 'unknown tag <modul>'),
    ('<mcp-config>\n<module name="a" binary="b" speed="2"/>\n</mcp-config>', 2,
     'unknown attribute(s) speed on <module>'),
    ('<mcp-config>\n<module binary="b"/>\n</mcp-config>', 2, '<module> needs non-empty attribute(s) name'),
    ('<mcp-config>\n<module name="a" locale="internal"/>\n</mcp-config>', 2,
     'internal module "a" has no binary'),
    ('<mcp-config>\n<module name="a" binary="b" managed="sometimes"/>\n</mcp-config>', 2,
     'managed="sometimes" is not one of managed, unmanaged, critical'),
    ('<mcp-config>\n<module name="a" binary="b"/>\n<module name="a" binary="c"/>\n</mcp-config>',
     3, 'defined twice'),
    ('<mcp-config>\n<module name="a">\n<binary>b</binary>\n<binary>c</binary>\n</module>\n'
     '</mcp-config>', 4, 'names its binary twice'),
    ('<mcp-config>\n<module name="a" binary="b">\n<options>-n "open</options>\n</module>\n'
     '</mcp-config>', 3, 'cannot split arguments'),
    ('<?xml version="1.0"?>\n<!DOCTYPE mcp-config [<!ENTITY a "aaaa">]>\n<mcp-config/>', 2,
     'internal subset'),
    ('<mcp-config>\n<module name="a" binary="b">\n</mcp-config>', 3, 'not well-formed'),
    ('<mcp-config>\n<container name="c">\n<binary>b</binary>\n</container>\n</mcp-config>', 3,
     'unknown tag <binary> in <container> (only <module>)'),
    ('<mcp-config>\n<container name="c"/>\n</mcp-config>', 2, 'container "c" holds no <module>'),
    ('<mcp-config>\n<container name="c" scheduling="fast">\n<module name="a" binary="p/a"/>\n</container>\n'
     '</mcp-config>', 2, 'scheduling "fast" is not one of threads, cooperative'),
    ('<mcp-config>\n<container name="c" scheduling="cooperative" quantum="1">\n<module name="a" binary="p/a"/>\n'
     '</container>\n</mcp-config>', 2, 'quantum="1" is not a number of seconds from 0 to 0.1'),
    ('<mcp-config>\n<container name="c" quantum="0.01">\n<module name="a" binary="p/a"/>\n</container>\n'
     '</mcp-config>', 2, 'a quantum is only for scheduling="cooperative"'),
    ('<mcp-config>\n<container name="c">\n<module name="a" binary="/usr/bin/a"/>\n</container>\n'
     '</mcp-config>', 3, 'module "a" of container "c" must be internal'),
    ('<mcp-config>\n<container name="c">\n<module name="a"/>\n</container>\n</mcp-config>', 3,
     'module "a" of container "c" must be internal'),
    ('<mcp-config>\n<container name="c">\n<module name="a" binary="p/a"/>\n</container>\n'
     '<container name="c">\n<module name="b" binary="p/b"/>\n</container>\n</mcp-config>', 5, 'defined twice'),
    ('<mcp-config>\n<module name="c" binary="p/c"/>\n<container name="c">\n<module name="a" binary="p/a"/>\n'
     '</container>\n</mcp-config>', 3, 'container "c" has the name of a module'),
    ('<mcp-config>\n<container name="c" size="2">\n<module name="a" binary="p/a"/>\n</container>\n'
     '</mcp-config>', 2, 'unknown attribute(s) size on <container>'),
])
def test_bad_config_is_refused(tmp_path: pathlib.Path, text: str, line: int, reason: str) -> None:
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as caught:
        read_mcp_config(path)
    assert (caught.value.path, caught.value.line) == (str(path), line), str(caught.value)
    assert reason in caught.value.reason


def test_huge_config_is_refused(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, '<mcp-config>' + ' ' * (2 << 20) + '</mcp-config>')
    with pytest.raises(ConfigError, match='larger than'):
        read_mcp_config(path)


@pytest.mark.parametrize('mapping, line, reason', [
    ('<connect module="A">\n<input interface="Foo" source="Bar"/>\n'
     '<input interface="Egomotion" source="Bar"/>\n</connect>', 4,
     'mapping connects Egomotion object "*" of module "A" to stream "Bar", which the mapping at '),
    ('<connect module="A">\n<input interface="Fooo" source="Bar"/>\n</connect>', 3,
     'unknown interface "Fooo"'),
    ('<connect module="A">\n<input interface="Foo"/>\n</connect>', 3, '<input> needs non-empty attribute(s) source'),
    ('<connect module="A">\n<output interface="Foo" source="Bar"/>\n</connect>', 3,
     'unknown tag <output>'),
])
def test_bad_mapping_is_refused(tmp_path: pathlib.Path, mapping: str, line: int,
                                reason: str) -> None:
    config = read_mcp_config(write(tmp_path, '<mcp-config><module name="A" binary="a"/>'
                                   '</mcp-config>'))
    path = write(tmp_path, f'<mcp-mappings>\n{mapping}\n</mcp-mappings>', 'map.xml')
    with pytest.raises(ConfigError) as caught:
        read_mcp_mappings(path, config)
        validate(config, load_all())
    assert (caught.value.path, caught.value.line) == (str(path), line), str(caught.value)
    assert reason in caught.value.reason


def test_mapping_for_a_listed_module_and_known_interface_is_accepted(tmp_path) -> None:
    config = read_mcp_config(write(tmp_path, '<mcp-config><module name="A" binary="a"/>'
                                   '</mcp-config>'))
    read_mcp_mappings(write(tmp_path, '<mcp-mappings><connect module="A"><input interface="Foo" '
                            'source="Bar"/></connect></mcp-mappings>', 'map.xml'), config)
    validate(config, load_all())
    assert [(m.interface, m.source, m.object) for m in config.mappings_for('A')] == \
        [('Foo', 'Bar', '')]
    assert McpConfig().mappings_for('A') == []


def test_guide_chapter1_files_as_printed_are_accepted() -> None:
    """Chapter 1 maps BlindTeleop without listing it: it becomes an external module, and the
    warning names the mappings file and the line."""
    directory = ROOT / 'config' / 'guide-ch1'
    config = read_mcp_config(directory / 'mcp-config.xml')
    mappings = directory / 'mcp-mappings.xml'
    read_mcp_mappings(mappings, config)
    warnings = validate(config, load_all())
    assert list(config.modules)[:5] == ['VectorMover', 'laserAvoider', 'HollowayLMS',
                                        'safePTUserver', 'HollowayRFlex']
    assert config.modules['BlindTeleop'].locale == ProcessLocale.EXTERNAL
    line = next(n for n, text in enumerate(mappings.read_text().splitlines(), 1)
                if 'SimpleAvoider' in text)
    assert warnings == [f'{mappings}:{line}: module "BlindTeleop" is named only in the mappings, '
                        'not in the MCP configuration: watched as an external module (the MCP '
                        'cannot start it)']
    assert config.warnings == warnings
    assert [m.object for m in config.mappings_for('laserAvoider')] == \
        ['LaserClient', 'EgoClient', 'NavClient']


def test_wiring_names_both_types() -> None:
    from wurde_mcp.config import Mapping
    from wurde_mcp.wiring import consumer_conflict, supplier_conflict
    mapping = Mapping('Teleop', 'Egomotion', 'RFlexMotion', 'EgoClient', 'm.xml', 7)
    assert supplier_conflict(mapping, 'RFlex', [('Egomotion', 'RFlexMotion')]) is None
    assert supplier_conflict(mapping, 'RFlex', [('RangeFinder', 'RFlexMotion')]) == (
        'mapping connects Egomotion object "EgoClient" of module "Teleop" to stream '
        '"RFlexMotion", but module "RFlex" supplies that stream as RangeFinder')
    assert consumer_conflict(mapping, [('Egomotion', 'EgoClient')]) is None
    assert 'declares "EgoClient" as PTUnit' in consumer_conflict(mapping, [('PTUnit', 'EgoClient')])


def test_a_container_holds_its_modules(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, '<mcp-config>\n<module name="alone" binary="p/x"/>\n<container name="box">\n'
                           '<module name="a" binary="wurde_drivers/dummy_base"><options>-n a</options></module>\n'
                           '<module name="b" binary="my_robot.modules:main"/>\n</container>\n</mcp-config>')
    config = read_mcp_config(path)
    assert {name: spec.container for name, spec in config.modules.items()} == {'alone': '', 'a': 'box', 'b': 'box'}
    assert config.modules['a'].args == ['-n', 'a'] and config.containers == {'box': f'{path}:3'}
    assert config.cooperative == {}
    path.write_text(path.read_text().replace('<container name="box">',
                                             '<container name="box" scheduling="cooperative">'))
    assert read_mcp_config(path).cooperative == {'box': QUANTUM_S}
    path.write_text(path.read_text().replace('scheduling="cooperative"', 'scheduling="cooperative" quantum="0.005"'))
    assert read_mcp_config(path).cooperative == {'box': 0.005}


def test_pluto_container_is_config_pluto_in_one_container() -> None:
    """config/pluto-container runs the modules of config/pluto, as configured there, in one container."""
    alone = read_mcp_config(ROOT / 'config' / 'pluto' / 'mcp-config.xml')
    contained = read_mcp_config(ROOT / 'config' / 'pluto-container' / 'mcp-config.xml')
    assert list(contained.containers) == ['robot']
    assert {spec.container for spec in contained.modules.values()} == {'robot'}
    assert [(s.name, s.binary, s.args, s.managed) for s in contained.modules.values()] == \
        [(s.name, s.binary, s.args, s.managed) for s in alone.modules.values()]


def test_the_manuals_container_example_loads(tmp_path: pathlib.Path) -> None:
    """docs/mcp.md's ``<container>`` example: two dummies in one container, the localModule alone."""
    path = write(tmp_path, example('container_config', 'xml'))
    config = read_mcp_config(path)
    assert {name: spec.container for name, spec in config.modules.items()} == \
        {'PlutoBase': 'sensors', 'PlutoLaser': 'sensors', 'localModule': ''}
    assert config.modules['PlutoBase'].managed == ProcessType.CRITICAL
