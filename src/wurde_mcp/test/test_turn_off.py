"""turn_off NAME reaches a running module by its CommsManager name, with or without an MCP
(guide 7.1): Quit goes to the module's heartbeat stream directly when no MCP supervises it.
turn_off alone, with no MCP of its host's name answering, quits the modules one by one and leaves
an MCP of another name running."""

from __future__ import annotations

import os
import subprocess
import sys

from mcp_fixture import WORKER, start_mcp, worker, write_config
from wurde_core import ProcessType, StatusMode
from wurde_testing import ChildProcess, find_executable


def turn_off(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, find_executable('wurde_mcp', 'turn_off'), *args],
                          capture_output=True, text=True, timeout=90, check=False)


def test_turn_off_ends_a_module_with_no_mcp_running(ros_domain: int) -> None:
    with ChildProcess([WORKER, '-n', 'Foo']) as foo:
        off = turn_off('Foo')
        assert off.returncode == 0, off.stderr
        assert 'sent Quit to Foo directly' in off.stdout
        assert foo.process.wait(timeout=30) == 0


def test_turn_off_of_an_unknown_name_fails_loudly(ros_domain: int) -> None:
    with ChildProcess([WORKER, '-n', 'Present']):
        off = turn_off('Absent')  # Present is found by no name: turn_off waits, then says so
    assert off.returncode == 1 and 'no module Absent answers' in off.stderr


def test_turn_off_reaches_a_module_the_mcp_does_not_supervise(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Kept') + worker('Spare', 'critical'))
    with start_mcp(tmp_path, config, mappings, '-a'):
        table.until(lambda r: r['Kept']['status'] == StatusMode.ACTIVE, 'Kept active')
        # each module tells its managed state in its heartbeat: the MCP's, or unmanaged by hand
        assert table.heartbeat_info('Kept').managed.get_value() == ProcessType.MANAGED
        assert table.heartbeat_info('Spare').managed.get_value() == ProcessType.CRITICAL
        with ChildProcess([WORKER, '-n', 'Stray'], env=dict(os.environ)) as stray:
            assert table.heartbeat_info('Stray').managed.get_value() == ProcessType.UNMANAGED
            off = turn_off('Stray')
            assert off.returncode == 0, off.stderr
            assert 'sent Quit to Stray directly' in off.stdout
            assert stray.process.wait(timeout=30) == 0
        off = turn_off('Kept')  # supervised: through the MCP, which keeps it down
        assert 'asked the MCP on mcp_control to quit Kept' in off.stdout
        rows = table.until(lambda r: r['Kept']['status'] == StatusMode.DEAD, 'Kept quit')
        assert rows['Kept']['restarts'] == 0


def test_turn_off_all_without_its_mcp_leaves_another_mcp_running(tmp_path, ros_domain: int) -> None:
    config, mappings = write_config(tmp_path, '')
    with start_mcp(tmp_path, config, mappings, '-a', '-n', 'MCP_B') as mcp_b, \
            ChildProcess([WORKER, '-n', 'Loose']) as loose:
        off = turn_off()            # this shell's MCP is the seed's MCP, which is not running
        assert off.returncode == 0, off.stderr
        assert 'sent Quit to Loose directly' in off.stdout and 'MCP_B is an MCP: left running' in off.stdout
        assert loose.process.wait(timeout=30) == 0
        assert mcp_b.process.poll() is None
