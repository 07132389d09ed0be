"""Every module's node serves ROS 2 parameters: its WURDE options and role configuration,
read-only, under one mapping (wurde_core.parameters), rclpy's use_sim_time, and the tunables it
declares; ``ros2 param dump`` gives a file ``--params-file`` takes back.  Real processes, real DDS,
rclpy's own parameter client (what ``ros2 param`` uses)."""

from __future__ import annotations

import dataclasses
import os
import pathlib

import pytest
from wurde_testing import ChildProcess, find_executable
from wurde_testing.manual import example
from wurde_testing.parameters import ParameterTool

from wurde_core import RoleConfiguration
from wurde_core.parameters import Tunables, configuration_values

ROLE_CONFIG = '''<?xml version="1.0"?>
<wurde-config>
  <log level="info"/>
  <option name="max-range" value="15"/>
  <module name="FooServer"><option name="rate" value="5"/></module>
  <module name="Other"><option name="secret" value="1"/></module>
</wurde-config>
'''


@pytest.fixture
def role_config(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> pathlib.Path:
    for name in ('WURDE_LOG_LEVEL', 'WURDE_DATA_DIR'):
        monkeypatch.delenv(name, raising=False)
    path = tmp_path / 'role-config.xml'
    path.write_text(ROLE_CONFIG)
    return path


def test_the_mapping_of_options_and_configuration(role_config: pathlib.Path) -> None:
    config = RoleConfiguration('FooServer').load(role_config)
    config.set_option('c', '3')                 # a command-line user option lands here
    values = configuration_values('FooServer', config)
    assert values['wurde.module'] == 'FooServer'
    assert values['wurde.role_config'] == str(role_config)
    assert values['wurde.log_level'] == 'info'
    assert values['wurde.option.max_range'] == '15'      # '-' is not legal in a parameter name
    assert values['wurde.option.c'] == '3'
    assert values['wurde.module_option.rate'] == '5'
    assert not any('secret' in name for name in values)   # another module's options are its own


def test_tunables_refuse_what_a_parameter_can_not_be() -> None:
    tunables = Tunables()
    tunables.declare('gain', 1.5, 'a gain', 0.0, 10.0)
    with pytest.raises(ValueError):
        tunables.declare('gain', 2.0, 'the same name again')
    with pytest.raises(ValueError):
        tunables.declare('wurde.mine', 1.0, 'inside the configuration\'s prefix')
    with pytest.raises(TypeError):
        tunables.declare('label', 'x', 'a range on a string', 0.0, 1.0)


def _foo_server(role_config: pathlib.Path, *ros_args: str) -> ChildProcess:
    return ChildProcess([find_executable('wurde_core', 'foo_server'), '-g', str(role_config),
                         *(['--ros-args', *ros_args] if ros_args else [])],
                        env=dict(os.environ))


def test_a_module_serves_its_configuration_read_only_and_takes_its_dump_back(
        ros_domain: int, role_config: pathlib.Path, tmp_path: pathlib.Path) -> None:
    with _foo_server(role_config):
        tool = ParameterTool('/FooServer')
        try:
            names = tool.names()
            assert {'use_sim_time', 'wurde.module', 'wurde.role_config', 'wurde.log_level',
                    'wurde.option.max_range', 'wurde.module_option.rate'} <= set(names)
            assert tool.get('wurde.module', 'wurde.option.max_range', 'wurde.module_option.rate') \
                == ['FooServer', '15', '5']
            assert tool.describe('wurde.log_level').read_only
            taken, reason = tool.set('wurde.log_level', 'debug')
            assert not taken and 'read-only' in reason
            assert tool.get('wurde.log_level') == ['info']
            assert tool.set('use_sim_time', True) == (True, '')
            assert tool.get('use_sim_time') == [True]
            dump = tool.dump()
        finally:
            tool.close()
    params = tmp_path / 'foo.yaml'
    params.write_text(dump)
    assert 'ros__parameters' in dump and 'max_range' in dump
    # the dump goes back in: use_sim_time is taken from it, the read-only values stay as read
    with _foo_server(role_config, '--params-file', str(params)) as again:
        tool = ParameterTool('/FooServer')
        try:
            assert tool.get('use_sim_time', 'wurde.option.max_range') == [True, '15']
            assert tool.names() == names
        finally:
            tool.close()
        assert again.process.poll() is None


def test_readme_tunable_example_runs_as_written(ros_domain: int, tmp_path: pathlib.Path) -> None:
    program = tmp_path / 'tuned.py'
    program.write_text(example('tunable', 'python'))
    with ChildProcess([str(program)]) as tuned:
        tuned.expect('gain 1.5')
        tool = ParameterTool('/Tuned')
        try:
            assert tool.set('gain', 3.0) == (True, '')
            tuned.expect('gain 3.0')
            taken, reason = tool.set('gain', 30.0)
            assert not taken and 'out of range' in reason
            taken, reason = tool.set('wurde.module', 'Other')
            assert not taken and 'read-only' in reason
            assert tool.get('gain', 'wurde.module') == [3.0, 'Tuned']
        finally:
            tool.close()
        assert tuned.stop() == 0


@dataclasses.dataclass(frozen=True)
class _Guard:
    stop: float = 0.15
    slow: float = 1.0

    def __post_init__(self) -> None:
        if not self.stop < self.slow:
            raise ValueError(f'stop {self.stop} must be below slow {self.slow}')


def test_tuned_settings_follow_their_parameters_and_refuse_what_the_settings_refuse(ros_domain: int) -> None:
    from rclpy.parameter import Parameter

    from wurde_core import CommsManager
    from wurde_core.parameters import TunedSettings
    manager = CommsManager('Tuned')
    try:
        tuned = TunedSettings(manager, _Guard(), {'stop': ('stop here, m', 0.0, 2.0),
                                                  'slow': ('slow from here, m', 0.1, 10.0)}, 'laser.')
        manager.step()                                  # the node, with the tunables declared
        first = tuned.current()
        assert first == _Guard() and tuned.current() is first      # unchanged: the same object
        result = manager.node.set_parameters([Parameter('laser.slow', value=0.1)])[0]
        assert not result.successful and 'must be below' in result.reason
        assert tuned.current() == _Guard()
        assert manager.node.set_parameters([Parameter('laser.slow', value=2.5)])[0].successful
        assert tuned.current() == _Guard(stop=0.15, slow=2.5)
    finally:
        manager.clean_up()


def test_out_of_range_says_which_starting_value_the_node_would_refuse() -> None:
    from wurde_core.parameters import out_of_range
    fields = {'stop': ('stop here, m', 0.0, 2.0), 'slow': ('slow from here, m', 0.1, 10.0)}
    assert out_of_range(_Guard(), fields, 'laser.') is None
    assert out_of_range(_Guard(stop=0.15, slow=12.0), fields, 'laser.') == \
        'laser.slow = 12.0 is out of range [0.1, 10.0]'
