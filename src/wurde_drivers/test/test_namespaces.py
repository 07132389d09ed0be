"""Two simulated robots in one ROS domain, each under its own MCP in its own namespace: the MCP
starts its modules in its namespace, the streams and standard topics follow it, a client of each
robot drives only that robot, and the tools reach only their own robot's MCP."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import time

from sim_fixture import Observer, sim_config
from wurde_core import StatusMode
from wurde_testing import ChildProcess, find_executable

BASE_ONLY = '''<?xml version="1.0"?>
<mcp-config>
  <module name="PlutoBase" managed="critical">
    <binary>wurde_drivers/dummy_base</binary>
    <options>-n PlutoBase</options>
  </module>
</mcp-config>
'''
NAMESPACES = ('/robot1', '/robot2')


def _robot(directory: pathlib.Path, namespace: str) -> ChildProcess:
    sim_config(directory)
    (directory / 'mcp-config.xml').write_text(BASE_ONLY)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    return ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(directory / 'mcp-config.xml'),
                         '-m', str(directory / 'mcp-mappings.xml'), '-a',
                         '--ros-args', '-r', f'__ns:={namespace}'], env=env)


def _tool(name: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, find_executable('wurde_mcp', name), *args],
                          capture_output=True, text=True, timeout=120, check=False)


def _status(observer: Observer, module: str) -> StatusMode | None:
    """The module's status in the newest table of the observer's MCP."""
    if not observer.events['mcp_control']:
        return None
    table = observer.events['mcp_control'][-1][1]
    return {n: StatusMode(s.value) for n, s in zip(table.module_names, table.module_status)}.get(module)


def test_two_robots_share_a_domain_without_cross_talk(ros_domain: int, tmp_path: pathlib.Path) -> None:
    streams = {'PlutoBaseTruth': 'Egomotion', 'PlutoBaseCommand': 'ActuatorState',
               'mcp_control': 'SimpleControl'}
    observers = {ns: Observer(streams, namespace=ns) for ns in NAMESPACES}
    one, two = observers['/robot1'], observers['/robot2']
    try:
        with _robot(tmp_path / 'r1', '/robot1'), _robot(tmp_path / 'r2', '/robot2') as mcp2:
            for observer in observers.values():
                observer.until(lambda o: len(o.events['PlutoBaseTruth']) >= 2, 'the truth of its robot',
                               timeout=90)
            start = one.events['PlutoBaseTruth'][0][1].location.x
            assert two.events['PlutoBaseTruth'][0][1].location.x == start   # same map, same start

            def drive() -> None:
                one.request('PlutoBaseCommand', cmd_flags=0, velocity=[0.3, 0.0])

            sent = 0.0

            def driven(o: Observer) -> bool:  # the command resent: the base's watchdog stops it
                nonlocal sent
                if time.monotonic() - sent > 0.5:
                    drive()
                    sent = time.monotonic()
                return o.events['PlutoBaseTruth'][-1][1].location.x > start + 0.3

            one.until(driven, 'robot1 driven 0.3 m')
            seen = len(two.events['PlutoBaseTruth'])
            two.until(lambda o: len(o.events['PlutoBaseTruth']) >= seen + 10, 'more truth from robot2')
            assert all(m.location.x == start for _, m in two.events['PlutoBaseTruth'])  # never moved

            # The graph as this process discovers it (each publisher is discovered on its own:
            # data of one topic says nothing of another's discovery, so wait for them).
            wanted = {'/robot1/wurde/PlutoBaseTruth/data', '/robot2/wurde/PlutoBaseTruth/data',
                      '/robot1/PlutoBase/odom', '/robot2/PlutoBase/odom'}
            one.until(lambda o: wanted <= {name for name, _ in o.manager.node.get_topic_names_and_types()},
                      'both robots in the graph')
            topics = {name for name, _ in one.manager.node.get_topic_names_and_types()}
            assert '/wurde/PlutoBaseTruth/data' not in topics and '/PlutoBase/odom' not in topics
            nodes_wanted = {('MCP', '/robot1'), ('PlutoBase', '/robot1'), ('MCP', '/robot2'), ('PlutoBase', '/robot2')}
            one.until(lambda o: nodes_wanted <= set(o.manager.node.get_node_names_and_namespaces()),
                      "both robots' nodes in the graph")

            # the tools reach the MCP of their namespace only
            listed = _tool('mcp_controller', 'status', '--ros-args', '-r', '__ns:=/robot2')
            assert listed.returncode == 0 and 'PlutoBase' in listed.stdout, listed.stderr
            off = _tool('turn_off', '--ros-args', '-r', '__ns:=/robot2')
            assert off.returncode == 0 and 'asked the MCP to quit every module' in off.stdout, off.stderr
            two.until(lambda o: _status(o, 'PlutoBase') == StatusMode.DEAD, "robot2's base quit")
            seen = len(one.events['PlutoBaseTruth'])        # robot1's MCP and base go on
            one.until(lambda o: len(o.events['PlutoBaseTruth']) >= seen + 10
                      and _status(o, 'PlutoBase') == StatusMode.ACTIVE, 'robot1 goes on, active')
            assert mcp2.process.poll() is None                    # robot2's MCP did not quit
    finally:
        for observer in observers.values():
            observer.close()
