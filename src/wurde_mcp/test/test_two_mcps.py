"""Two MCPs in one domain, as on two hosts (one MCP per host; the netns version is
``test_two_hosts.py``): each answers and commands only its own modules, watches the other's
that its configuration lists as external, and a consumer on one is assigned a stream supplied
on the other."""

from __future__ import annotations

import os
import pathlib
import subprocess
import time

from mcp_fixture import Table, listener_script, start_mcp, wait_output, worker, write_config
from wurde_core import StatusMode
from wurde_testing import find_executable

ACTIVE, DEAD = StatusMode.ACTIVE, StatusMode.DEAD

def _host(directory: pathlib.Path) -> pathlib.Path:
    directory.mkdir()
    return directory


def test_two_mcps_each_command_their_own(tmp_path, ros_domain) -> None:
    host_a, host_b = _host(tmp_path / 'a'), _host(tmp_path / 'b')
    # Host A: the seed's MCP ("MCP") supervising Server (it supplies Foo on Server_out) and Keeper.
    config_a, mappings_a = write_config(host_a, worker('Server') + worker('Keeper'))
    # Host B: MCP_B with Listener (its consumer assigned to A's stream) and A's modules watched.
    listener = listener_script(host_b)
    config_b, mappings_b = write_config(
        host_b, f'<module name="Listener" binary="{listener}"/>'
                '<module name="Server" locale="external"/><module name="Keeper" locale="external"/>',
        '<connect module="Listener">\n'
        '<input interface="Foo" source="Server_out" object="BarClient"/>\n</connect>')
    table_a, table_b = Table(), Table('mcp_control/MCP_B')
    log = host_b / 'mcp-modules' / 'Listener.log'
    try:
        with start_mcp(host_a, config_a, mappings_a, '-a') as mcp_a:
            rows = table_a.until(lambda r: all(x['status'] == ACTIVE for x in r.values()),
                                 'A\'s modules active')
            pids = {name: row['pid'] for name, row in rows.items()}
            with start_mcp(host_b, config_b, mappings_b, '-a', '-n', 'MCP_B') as mcp_b:
                # B's table lists its own module and A's, each alive; A's lists only its own.
                table_b.until(lambda r: all(x['status'] == ACTIVE for x in r.values())
                              and all(r[n]['pid'] == p for n, p in pids.items()),
                              'all alive in B\'s table')
                assert set(table_a.refresh()) == {'Server', 'Keeper'}
                # Each module says which MCP it belongs to.
                assert table_b.heartbeat_info('Listener').mcp.get_value() == 'MCP_B'
                assert table_b.heartbeat_info('Server').mcp.get_value() == 'MCP'
                # STRAT_ASSIGNED across the two: B's MCP gave Listener A's stream.
                wait_file_lines(log, 'VALUE Server', table_b)
                # turn_off on host B (its shell names MCP_B; B's table lists Server as external)
                # finds the MCP Server belongs to, which stops it and keeps it down.
                env = dict(os.environ, WURDE_MCP_NAME='MCP_B')
                off = subprocess.run([find_executable('wurde_mcp', 'turn_off'), 'Server'],
                                     env=env, capture_output=True, text=True, timeout=120)
                assert off.returncode == 0, off.stderr
                assert 'asked the MCP on mcp_control to quit Server' in off.stdout, off.stdout
                table_a.until(lambda r: r['Server']['status'] == DEAD, 'Server stopped by A')
                wait_output(mcp_a, r'MCP: Server exited with code 0')
                # B is shut down: it quits its own module and leaves A's alone.
                assert mcp_b.stop(timeout=60) == 0, mcp_b.stderr
                wait_output(mcp_b, r'MCP: Keeper belongs to MCP "MCP": it is watched, not '
                                   r'commanded, from here')
                wait_output(mcp_b, r'MCP: Listener ended .* after Quit')
            rows = table_a.until(lambda r: r['Keeper']['status'] == ACTIVE, 'Keeper active on A')
            assert rows['Keeper']['pid'] == pids['Keeper'] and rows['Keeper']['restarts'] == 0
            assert rows['Server']['status'] == DEAD and rows['Server']['restarts'] == 0
    finally:
        table_a.close()
        table_b.close()


def wait_file_lines(path: pathlib.Path, text: str, table: Table, count: int = 3) -> None:
    """Wait (failure bound 120 s) for ``count`` lines starting with ``text`` in ``path``."""
    deadline = time.monotonic() + 120
    while True:
        lines = path.read_text().splitlines() if path.exists() else []
        if sum(line.startswith(text) for line in lines) >= count:
            return
        assert time.monotonic() < deadline, f'{count} × {text!r} not in {path}:\n{lines}'
        table.refresh()
        table.manager.wait(0.1)
