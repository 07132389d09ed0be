"""RoleConfiguration: the seed's files, environment overrides, refusals with file and line."""

from __future__ import annotations

import pathlib

import pytest

from wurde_core import ConfigError, RoleConfiguration

APPENDIX = '''<?xml version="1.0" encoding="UTF-8" ?>
<robot>
<wurde-config xmlns:xs="http://www.w3.org/2001/XMLSchema-instance"
xmlns="http://wurde.sf.net/wurde-config"
xs:schemalocation="http://wurde.sf.net/wurde-config wurde.xsd">
<data-directory location="/home/fwph/data"/>
<config-directory location="/home/fwph/config"/>
<bin-directory location="/usr/local/bin/"/>
<log directory="/home/fwph/logs/" level="info"/>
<mcp mcp-config="local-config.xml">
<comment>The config files should be in the config directory.</comment>
</mcp>
<option name="example" value="15">
<comment>Option entities should always be commented!</comment>
</option>
<module name="FooServer"><option name="rate" value="5"/></module>
</wurde-config>
<mcp-config/>
</robot>
'''


@pytest.fixture
def clean_env(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ('WURDE_CONFIG_DIR', 'WURDE_DATA_DIR', 'WURDE_BIN_DIR', 'WURDE_MCP_CONFIG',
                 'WURDE_MCP_MAPPINGS', 'WURDE_LOG_LEVEL', 'WURDE_LOG_DIRECTORY'):
        monkeypatch.delenv(name, raising=False)


def test_appendix_combined_file_is_read(tmp_path: pathlib.Path, clean_env: None) -> None:
    path = tmp_path / 'robot.xml'
    path.write_text(APPENDIX)
    config = RoleConfiguration('FooServer').load(path)
    assert config.get_data_directory() == '/home/fwph/data'
    assert config.get_config_directory() == '/home/fwph/config'
    assert config.get_bin_directory() == '/usr/local/bin/'
    assert config.get_log_directory() == '/home/fwph/logs/'
    assert config.get_log_level() == 'info'
    assert config.get_mcp_config_file() == '/home/fwph/config/local-config.xml'
    assert config.get_mcp_mappings_file() == '/home/fwph/config/mcp-mapping.xml'
    assert config.have_option('example') and config.get_option('example') == '15'
    assert not config.have_option('absent') and config.get_option('absent') == 'empty'
    assert config.have_module_option('FooServer', 'rate')
    assert config.get_module_option('FooServer', 'rate') == '5'
    assert config.get_module_option('Other', 'rate') == 'empty'
    assert config.get_module_name() == 'FooServer'


def test_defaults_without_a_file(clean_env: None) -> None:
    config = RoleConfiguration('M')
    assert config.get_log_level() == 'debug'
    assert config.get_mcp_config_file() == 'mcp-config.xml'
    assert config.get_config_directory() == '.'


def test_environment_overrides_the_file(tmp_path: pathlib.Path, clean_env: None,
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / 'robot.xml'
    path.write_text(APPENDIX)
    monkeypatch.setenv('WURDE_CONFIG_DIR', '/etc/robot')
    monkeypatch.setenv('WURDE_DATA_DIR', '/var/data')
    monkeypatch.setenv('WURDE_BIN_DIR', '/opt/bin')
    monkeypatch.setenv('WURDE_MCP_CONFIG', 'other.xml')
    monkeypatch.setenv('WURDE_MCP_MAPPINGS', '/abs/map.xml')
    monkeypatch.setenv('WURDE_LOG_LEVEL', 'error')
    monkeypatch.setenv('WURDE_LOG_DIRECTORY', '/var/log/robot')
    config = RoleConfiguration('M').load(path)
    assert config.get_config_directory() == '/etc/robot'
    assert config.get_data_directory() == '/var/data'
    assert config.get_bin_directory() == '/opt/bin'
    assert config.get_mcp_config_file() == '/etc/robot/other.xml'
    assert config.get_mcp_mappings_file() == '/abs/map.xml'
    assert config.get_log_level() == 'error'
    assert config.get_log_directory() == '/var/log/robot'


@pytest.mark.parametrize('body, line, reason', [
    ('<wurde-config>\n<datadirectory location="x"/>\n</wurde-config>', 2,
     'unknown tag <datadirectory>'),
    ('<wurde-config>\n<log level="loud"/>\n</wurde-config>', 2, 'log level "loud"'),
    ('<wurde-config>\n<option name="a"/>\n</wurde-config>', 2, '<option> needs attribute(s) value'),
    ('<wurde-config>\n<bin-directory place="x"/>\n</wurde-config>', 2, 'unknown attribute(s) place on <bin-directory>'),
    ('<wurde-config>\n<module name="m">\n<flag/>\n</module>\n</wurde-config>', 3,
     'unknown tag <flag>'),
    ('<wurde-config>\n<option name="a" value="b">\n</wurde-config>', 3, 'not well-formed'),
    ('<mcp-config/>', 1, 'root element is <mcp-config>'),
    ('<robot>\n</robot>', 1, 'exactly one <wurde-config>'),
])
def test_bad_files_are_refused_with_file_line_and_reason(tmp_path: pathlib.Path, body: str,
                                                         line: int, reason: str) -> None:
    path = tmp_path / 'role-config.xml'
    path.write_text(body)
    with pytest.raises(ConfigError) as caught:
        RoleConfiguration('M').load(path)
    assert caught.value.path == str(path) and caught.value.line == line, str(caught.value)
    assert reason in caught.value.reason


def test_unknown_log_level_in_environment_is_refused(clean_env: None,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv('WURDE_LOG_LEVEL', 'chatty')
    with pytest.raises(ConfigError, match='log level "chatty"'):
        RoleConfiguration('M').get_log_level()
