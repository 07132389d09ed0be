"""The MCP as a lifecycle node, its registration pass, and stream assignment to modules."""

from __future__ import annotations

import os
import pathlib
import re
import signal
import subprocess
import sys
import time

from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.executors import SingleThreadedExecutor

from mcp_fixture import (WORKER, Table, alive, listener_script, start_mcp, wait_output, worker,
                         write_config)
from wurde_core import RunState, StatusMode
from wurde_core.interfaces import robot_object_class
from wurde_mcp.supervisor import CMD_START, CMD_STOP
from wurde_testing import ChildProcess, find_executable
from wurde_testing.lifecycle import change_state, get_state

ACTIVE, DEAD = StatusMode.ACTIVE, StatusMode.DEAD


class _Spinner:
    """Spins the table's node for the lifecycle clients, refreshing the table meanwhile."""

    def __init__(self, table: Table) -> None:
        self.table = table
        self.executor = SingleThreadedExecutor(context=table.manager.context)
        self.executor.add_node(table.manager.node)

    def __call__(self, timeout: float) -> None:
        self.executor.spin_once(timeout_sec=timeout)
        self.table.refresh()

    def close(self) -> None:
        self.executor.remove_node(self.table.manager.node)


def test_lifecycle_transitions_drive_the_modules(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Life'))
    with start_mcp(tmp_path, config, mappings, '--lifecycle') as mcp:
        node = table.manager.node
        change = node.create_client(ChangeState, '/MCP/change_state')
        get = node.create_client(GetState, '/MCP/get_state')
        spin = _Spinner(table)
        assert get_state(spin, get) == 'unconfigured'
        # The node that answered is the MCP's one node (the graph's node names come with discovery,
        # after the service has matched: waited for).
        deadline = time.monotonic() + 30
        while 'MCP' not in node.get_node_names():
            assert time.monotonic() < deadline, f'no node MCP in the graph: {node.get_node_names()}'
            table.refresh()
            time.sleep(0.05)
        names = node.get_node_names()
        assert names.count('MCP') == 1 and 'mcp' not in names, names

        def transition(tid: int, goal: str) -> None:
            assert change_state(spin, change, get, tid, goal)

        transition(Transition.TRANSITION_CONFIGURE, 'inactive')  # the registration pass runs here
        assert 'Life.log' in [p.name for p in (tmp_path / 'mcp-modules').iterdir()]
        assert '-r' in (tmp_path / 'mcp-modules' / 'Life.log').read_text()
        rows = table.until(lambda r: 'Life' in r, 'module table')
        assert rows['Life']['pid'] == 0 or not alive(rows['Life']['pid'])
        transition(Transition.TRANSITION_ACTIVATE, 'active')
        rows = table.until(lambda r: r['Life']['status'] == ACTIVE, 'Life started')
        pid = rows['Life']['pid']
        transition(Transition.TRANSITION_DEACTIVATE, 'inactive')
        table.until(lambda r: r['Life']['state'] == RunState.IDLE, 'Life idle')
        transition(Transition.TRANSITION_CLEANUP, 'unconfigured')
        deadline = time.monotonic() + 20
        while alive(pid):
            assert time.monotonic() < deadline, 'cleanup left the module running'
            time.sleep(0.05)
        assert get_state(spin, get) == 'unconfigured'
        assert mcp.process.poll() is None
        spin.close()


def test_assigned_stream_and_supplier_started_on_demand(tmp_path, table) -> None:
    client_script = tmp_path / 'assigned.py'
    client_script.write_text(
        '#!/usr/bin/env python3\n'
        'import sys\n'
        'from wurde_core import CommsManager, ConnectionStrategy, RunState\n'
        'from wurde_core.interfaces import Foo\n'
        'm = CommsManager("Client"); m.parse_options(sys.argv); m.set_sleep(0.05)\n'
        'foo = Foo(ConnectionStrategy.ASSIGNED, "BarClient"); m.register_consumer(foo)\n'
        'while m.run_update() != RunState.QUIT:\n'
        '    pass\n'
        'm.clean_up()\n')
    client_script.chmod(0o755)
    modules = (worker('Server') +
               f'<module name="Client" binary="{client_script}"/>')
    mappings_xml = ('<connect module="Client">\n'
                    '<input interface="Foo" source="Server_out" object="BarClient"/>\n</connect>')
    config, mappings = write_config(tmp_path, modules, mappings_xml)
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Client')
    heartbeat.set_queue_mode(True)
    table.manager.register_consumer(heartbeat)
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        table.until(lambda r: all(x['status'] == ACTIVE for x in r.values()), 'both active')

        def consumed() -> list[str]:
            streams: list[str] = []
            while heartbeat.get_next_info():
                streams = heartbeat.info.consumed_streams.get_value()
            return streams

        deadline = time.monotonic() + 30
        while consumed() != ['Server_out']:
            assert time.monotonic() < deadline, 'Client never got its assigned stream'
            table.refresh()
            table.manager.wait(0.05)

        # Stop the supplier, then restart the client: its request makes the MCP start the
        # supplier again (start on demand).
        table.command(CMD_STOP, 'Server')
        table.until(lambda r: r['Server']['status'] == DEAD, 'Server stopped')
        table.command(CMD_STOP, 'Client')
        table.until(lambda r: r['Client']['status'] == DEAD, 'Client stopped')
        table.command(CMD_START, 'Client')
        try:
            table.until(lambda r: r['Server']['status'] == ACTIVE and
                        r['Client']['status'] == ACTIVE, 'Server started on demand for Client')
        except AssertionError as exc:
            raise AssertionError(f'{exc}\nMCP stderr:\n{mcp.stderr}') from None


def test_registration_pass_collects_capabilities(tmp_path, table) -> None:
    """Configure with -r runs: the MCP learns what Worker supplies before starting it."""
    config, mappings = write_config(tmp_path, worker('Cap'))
    with start_mcp(tmp_path, config, mappings, '-a'):
        table.until(lambda r: r['Cap']['status'] == ACTIVE, 'Cap active')
    log = (tmp_path / 'mcp-modules' / 'Cap.log').read_text()
    assert 'supplies Foo Cap_out' in log and 'capabilities of Cap sent to the MCP' in log
    assert WORKER in log


def test_assigned_consumer_receives_data_also_after_its_supplier_restarts(tmp_path, table) -> None:
    client_script = listener_script(tmp_path)
    modules = ('<module name="FooServer" binary="wurde_core/foo_server"/>'
               f'<module name="Listener" binary="{client_script}"/>')
    mappings_xml = ('<connect module="Listener">\n'
                    '<input interface="Foo" source="Bar" object="BarClient"/>\n</connect>')
    config, mappings = write_config(tmp_path, modules, mappings_xml)
    log = tmp_path / 'mcp-modules' / 'Listener.log'

    def values() -> list[float]:
        text = log.read_text() if log.exists() else ''
        complete = text[:text.rfind('\n') + 1]          # the listener may be writing the last line
        return [float(line.split()[-1]) for line in complete.splitlines()
                if line.startswith('VALUE FooServer')]

    def wait_for(predicate, what: str) -> None:
        # A failure bound, not a speed target: on a loaded machine FooServer's 25 values and
        # the restart's discovery have taken more than 40 s.
        deadline = time.monotonic() + 120
        while not predicate():
            assert time.monotonic() < deadline, f'{what}; listener log:\n{log.read_text()}'
            table.refresh()
            table.manager.wait(0.1)

    with start_mcp(tmp_path, config, mappings, '-a'):
        # Let the first FooServer count high, so that the restarted one (counting from 0 again)
        # is told apart by its values even if it is heard only after a few (discovery).
        wait_for(lambda: len(values()) >= 3 and max(values()) >= 25,
                 'no data through the assigned stream')
        rows = table.until(lambda r: r['FooServer']['status'] == ACTIVE, 'FooServer active')
        server_pid, restarts = rows['FooServer']['pid'], rows['FooServer']['restarts']
        seen = len(values())
        before = values()[-1]
        os.kill(server_pid, signal.SIGKILL)
        table.until(lambda r: r['FooServer']['restarts'] == restarts + 1 and
                    r['FooServer']['status'] == ACTIVE, 'FooServer restarted')
        # The listener keeps its stream: the restarted FooServer's values (from 0 again) arrive.
        wait_for(lambda: len([v for v in values()[seen:] if v < before]) >= 3,
                 'no data from the restarted supplier')


def test_turn_off_stops_everyone(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('X1') + worker('X2', 'critical'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        table.until(lambda r: all(x['status'] == ACTIVE for x in r.values()), 'all active')
        off = subprocess.run([sys.executable, find_executable('wurde_mcp', 'turn_off')],
                             capture_output=True, text=True, timeout=60, check=True)
        assert 'quit every module' in off.stdout
        rows = table.until(lambda r: all(x['status'] == DEAD for x in r.values()), 'all quit')
        assert all(x['restarts'] == 0 for x in rows.values())
        assert mcp.process.poll() is None


def test_guide_chapter1_files_as_printed_configure_and_run(tmp_path, table) -> None:
    """config/guide-ch1 (the guide's files as printed) is accepted by the running MCP: BlindTeleop,
    named only in the mappings, is watched as an external module and the warning says where."""
    root = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'guide-ch1'
    mappings = str(root / 'mcp-mappings.xml')
    with start_mcp(tmp_path, str(root / 'mcp-config.xml'), mappings, '-a') as mcp:
        warning = wait_output(mcp, rf'{re.escape(mappings)}:(\d+): module "BlindTeleop" is named '
                              'only in the mappings')
        assert 'SimpleAvoider' in pathlib.Path(mappings).read_text().splitlines()[
            int(warning[1]) - 1]
        rows = table.until(lambda r: 'BlindTeleop' in r and 'VectorMover' in r, 'module table')
        assert len(rows) == 6 and mcp.process.poll() is None


def test_supplier_known_only_at_run_time_contradicting_a_mapping_is_refused(tmp_path,
                                                                            table) -> None:
    """Ext (external, started by hand) supplies Ext_out as Foo; the mapping gives it to Reader
    as a RangeFinder.  The MCP learns it from Ext's heartbeat: it logs the mapping's file, line
    and both types, and refuses Reader that stream instead of letting it wait for data forever."""
    reader = tmp_path / 'reader.py'
    reader.write_text(
        '#!/usr/bin/env python3\n'
        'import sys\n'
        'from wurde_core import CommsManager, ConnectionStrategy, RunState\n'
        'from wurde_core.interfaces import RangeFinder\n'
        'm = CommsManager("Reader"); m.parse_options(sys.argv); m.set_sleep(0.1)\n'
        'm.register_consumer(RangeFinder(ConnectionStrategy.ASSIGNED, "Laser"))\n'
        'while m.run_update() != RunState.QUIT:\n'
        '    pass\n'
        'm.clean_up()\n')
    config, mappings = write_config(
        tmp_path, '<module name="Ext" locale="external"/>',
        '<connect module="Reader">\n<input interface="RangeFinder" source="Ext_out" '
        'object="Laser"/>\n</connect>')
    reason = ('mapping connects RangeFinder object "Laser" of module "Reader" to stream '
              '"Ext_out", but module "Ext" supplies that stream as Foo')
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        with ChildProcess([WORKER, '-n', 'Ext']):
            wait_output(mcp, re.escape(f'{mappings}:4: {reason}'), timeout=60)
            with ChildProcess([str(reader)]) as client:  # asks only once the MCP knows Ext
                wait_output(client, r'could not assign a stream to RangeFinder\("Laser"\): ' +
                            re.escape(f'{mappings}:4: {reason}'), timeout=60)
        assert mcp.process.poll() is None
