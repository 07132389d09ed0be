"""The MCP as the guide types it (6: ``mcp -c CONFIG -m MAPPINGS`` starts the system; ``--lifecycle``
waits for transitions), run states seen by a guide program's own loop (5.2.1), and a module's
heartbeat limit beyond 10 s trusted when it asks (6.1)."""

from __future__ import annotations

import pathlib
import time

import pytest
from mcp_fixture import Table, start_mcp, wait_file, wait_output, worker, write_config
from wurde_core import RunState, StatusMode
from wurde_mcp.supervisor import CMD_STATE
from wurde_testing import ChildProcess, find_executable

HERE = pathlib.Path(__file__).resolve().parent
GUIDE_LOOP = str(HERE / 'guide_loop.py')
#: guide_loop.py's loop turns before its long absences (its QUICK_TURNS).
QUICK_TURNS = 30
ACTIVE = StatusMode.ACTIVE


def guide_loop(name: str, options: str = '') -> str:
    """A module entry running guide_loop.py as ``name``."""
    return (f'<module name="{name}" binary="{GUIDE_LOOP}" managed="managed">'
            f'<options>-n {name} {options}</options></module>')


def test_the_guides_command_line_starts_the_system(tmp_path, table: Table) -> None:
    """No -a: the MCP configures, activates and starts its modules in Run."""
    config, mappings = write_config(tmp_path, worker('Typed'))
    with start_mcp(tmp_path, config, mappings):
        rows = table.until(lambda r: r.get('Typed', {}).get('status') == ACTIVE
                           and r['Typed']['state'] == RunState.RUN, 'Typed active in Run')
        assert rows['Typed']['pid'] > 0


def test_the_lifecycle_flag_waits_for_a_transition(tmp_path, table: Table) -> None:
    """--lifecycle: the table lists nothing (no configuration read) and no module runs, however
    long one waits; the module's log would be the registration pass's first trace."""
    config, mappings = write_config(tmp_path, worker('Waiting'))
    with start_mcp(tmp_path, config, mappings, '--lifecycle') as mcp:
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:      # the unconfigured MCP publishes no module rows
            assert not table.refresh(), table.rows
            table.manager.wait(0.1)
        assert not (tmp_path / 'mcp-modules' / 'Waiting.log').exists()
        assert mcp.process.poll() is None


@pytest.mark.process
def test_a_and_lifecycle_together_are_refused(tmp_path) -> None:
    config, mappings = write_config(tmp_path, worker('Never'))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', config, '-m', mappings, '-a',
                       '--lifecycle']) as mcp:
        assert mcp.process.wait(timeout=60) == 2
    assert '-a and --lifecycle contradict each other' in mcp.stderr


def test_a_guide_loop_sees_idle_and_reset(tmp_path, table: Table) -> None:
    """With set_return_states, run_update hands Idle and Reset to the program's loop; its
    set_run after the Reset brings it back to Run."""
    config, mappings = write_config(tmp_path, guide_loop('Guide', '-s'))
    log = tmp_path / 'mcp-modules' / 'Guide.log'
    with start_mcp(tmp_path, config, mappings):
        table.until(lambda r: r.get('Guide', {}).get('status') == ACTIVE, 'Guide active')
        wait_file(log, 'Guide: state RUN')
        table.command(CMD_STATE, 'Guide', RunState.IDLE)
        wait_file(log, 'Guide: state IDLE')
        table.until(lambda r: r['Guide']['state'] == RunState.IDLE, 'Guide reported Idle')
        table.command(CMD_STATE, 'Guide', RunState.RUN)
        table.until(lambda r: r['Guide']['state'] == RunState.RUN, 'Guide back in Run')
        table.command(CMD_STATE, 'Guide', RunState.RESET)
        wait_file(log, 'Guide: reset handled')
        table.until(lambda r: r['Guide']['state'] == RunState.RUN, 'Guide in Run after its Reset')
    lines = [line for line in log.read_text().splitlines() if line.startswith('Guide: ')]
    states = [line for line in lines if 'state' in line or 'reset' in line]
    start = states.index('Guide: state IDLE')
    assert states[start:start + 5] == ['Guide: state IDLE', 'Guide: state RUN', 'Guide: state RESET',
                                       'Guide: reset handled', 'Guide: state RUN'], lines


def test_a_trusted_long_ttl_is_waited_for(tmp_path, table: Table) -> None:
    """Three modules announce a 15 s TTL: Trusted asks to be trusted and stays away 12 s at a
    time — never restarted; Hung asks too and stops beating — restarted; Clamped stays away 12 s
    without asking — the 10 s ceiling makes it a zombie, restarted."""
    config, mappings = write_config(tmp_path, guide_loop('Trusted', '-t 15 -T -b 12')
                                    + guide_loop('Hung', '-t 15 -T -q')
                                    + guide_loop('Clamped', '-t 15 -b 12'))
    trusted_log = tmp_path / 'mcp-modules' / 'Trusted.log'
    with start_mcp(tmp_path, config, mappings) as mcp:
        rows = table.until(lambda r: len(r) == 3 and all(x['status'] == ACTIVE for x in r.values()),
                           'all three active', timeout=90)
        pid = rows['Trusted']['pid']
        # The verdicts, not just restarts: on a loaded machine a module that hangs before the MCP
        # has heard it beat is given up on by the start timeout instead, and started again.
        wait_output(mcp, r'Hung missed its TTL \(15\.000 s\)', timeout=120)
        wait_output(mcp, r'Clamped missed its TTL \(10\.000 s\)', timeout=120)
        table.until(lambda r: r['Hung']['restarts'] >= 1 and r['Clamped']['restarts'] >= 1,
                    'Hung and Clamped restarted', timeout=60)
        # Trusted's third long absence has begun: two 12 s gaps lived through.
        wait_file(trusted_log, f'away 12.0 s after turn {QUICK_TURNS + 2}', timeout=90)
        rows = table.refresh()
        assert rows['Trusted']['restarts'] == 0 and rows['Trusted']['pid'] == pid, rows
        assert rows['Trusted']['status'] == ACTIVE, rows
    verdicts = [line for line in mcp.stderr.splitlines() if 'missed its TTL' in line]
    assert not any('Trusted' in line for line in verdicts), verdicts
