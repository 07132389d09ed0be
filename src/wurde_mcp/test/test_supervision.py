"""The MCP end to end: real module processes, real signals, real DDS."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

import pytest
from mcp_fixture import alive, start_mcp, wait_file, wait_output, worker, write_config
from wurde_core import RunState, StatusMode
from wurde_mcp.supervisor import CMD_START, CMD_STATE, CMD_STOP
from wurde_testing import ChildProcess, find_executable

ACTIVE, DEAD, FAILED, ZOMBIE = (StatusMode.ACTIVE, StatusMode.DEAD, StatusMode.FAILED,
                                StatusMode.ZOMBIE)


def active(*names: str):
    """Whether the table lists every one of ``names`` as ACTIVE (a table without them, from an
    MCP not yet configured or not this test's, does not do)."""
    return lambda rows: all(n in rows and rows[n]['status'] == ACTIVE for n in names)


def test_kill9_of_a_managed_module_restarts_it_and_disturbs_no_other(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('A') + worker('B'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        rows = table.until(active('A', 'B'), 'A and B active')
        a_pid, b_pid = rows['A']['pid'], rows['B']['pid']
        os.kill(a_pid, signal.SIGKILL)
        rows = table.until(lambda r: r['A']['restarts'] == 1 and r['A']['status'] == ACTIVE
                           and r['A']['pid'] != a_pid, 'A restarted and alive')
        assert rows['B']['pid'] == b_pid and rows['B']['restarts'] == 0
        assert rows['B']['status'] == ACTIVE
        assert mcp.process.poll() is None
        # The new process knows it is a restart (WURDE_MCP_RESTART) and where its state is kept
        # (WURDE_MCP_STATE); B's first one knows it is not a restart.
        wait_file(tmp_path / 'mcp-modules' / 'A.log',
                  f'A: start 1 under this MCP, state in {tmp_path / "mcp-modules" / "A.resume"}')
        assert 'B: start 0 under this MCP' in (tmp_path / 'mcp-modules' / 'B.log').read_text()


def test_a_hung_module_becomes_a_zombie_and_is_restarted(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Hung'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        pid = table.until(active('Hung'), 'Hung active')['Hung']['pid']
        os.kill(pid, signal.SIGSTOP)
        table.until(lambda r: r['Hung']['pid'] != pid and r['Hung']['status'] == ACTIVE,
                    'Hung replaced by a live process')
        assert wait_output(mcp, r'MCP: Hung missed its TTL \(1\.000 s\): zombie')
        assert not alive(pid)


def test_a_silent_module_that_works_is_left_alone_and_one_asleep_is_a_zombie(tmp_path, table) -> None:
    """Silent past the TTL is a zombie only when the process makes no progress
    (wurde_mcp.progress): a module spinning on the CPU for 2.5 s (TTL 1 s) keeps its pid; one
    asleep without a heartbeat is killed and replaced."""
    config, mappings = write_config(tmp_path, worker('Busy') + worker('Sleepy'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        rows = table.until(lambda r: r['Busy']['status'] == ACTIVE and r['Sleepy']['status'] == ACTIVE,
                           'both active')
        busy, sleepy = rows['Busy']['pid'], rows['Sleepy']['pid']
        os.kill(busy, signal.SIGUSR1)
        assert wait_output(mcp, r'MCP: Busy is silent past its TTL but its process is working')
        os.kill(sleepy, signal.SIGUSR2)
        rows = table.until(lambda r: r['Sleepy']['pid'] != sleepy and r['Sleepy']['status'] == ACTIVE,
                           'Sleepy replaced by a live process')
        verdict = wait_output(mcp, r'MCP: Sleepy missed its TTL \(1\.000 s\): zombie[^\n]*')
        # The verdict says where the hung process waited: its main thread in time.sleep.
        assert re.search(r'kernel wait\): [^\n]* S \w*nanosleep', verdict[0]), verdict[0]
        assert rows['Busy']['pid'] == busy and rows['Busy']['restarts'] == 0
        assert 'MCP: Busy missed its TTL' not in mcp.stdout + mcp.stderr


def test_unmanaged_module_is_left_dead(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Loose', 'unmanaged') + worker('Kept'))
    with start_mcp(tmp_path, config, mappings, '-a'):
        rows = table.until(active('Loose', 'Kept'), 'both active')
        os.kill(rows['Loose']['pid'], signal.SIGKILL)
        os.kill(rows['Kept']['pid'], signal.SIGKILL)
        # A first restart is started in the very look that sees the exit (no back-off), so a
        # table showing Loose DEAD with no restart shows that none was made.
        rows = table.until(lambda r: r['Loose']['status'] == DEAD and r['Kept']['restarts'] == 1
                           and r['Kept']['status'] == ACTIVE, 'Loose dead, Kept restarted')
        assert rows['Loose']['restarts'] == 0


def test_critical_module_down_idles_everyone_until_it_is_back(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Heart', 'critical') + worker('Limb'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        rows = table.until(active('Heart', 'Limb'), 'both active')
        limb = rows['Limb']['pid']
        os.kill(rows['Heart']['pid'], signal.SIGKILL)
        wait_output(mcp, r'critical module Heart is down: every other module goes Idle')
        # Limb enters Idle (its hook says so).  The MCP's table is not asked to show it: the
        # table shows each module's newest state, and a critical module back before Limb's next
        # loop turn makes Limb's Idle last no time — Idle and Run come in one exchange (r45:
        # Heart alive 0.38 s after the kill, Limb's loop sleeps 0.5 s).
        log = tmp_path / 'mcp-modules' / 'Limb.log'
        wait_file(log, 'Limb: idle')
        rows = table.until(lambda r: r['Heart']['status'] == ACTIVE and r['Heart']['restarts'] == 1
                           and r['Limb']['state'] == RunState.RUN, 'Heart back, Limb running again')
        deadline = time.monotonic() + 30   # failure bound: the hook's line follows the table
        while 'Limb: running again' not in log.read_text().split('Limb: idle', 1)[1]:
            assert time.monotonic() < deadline, log.read_text()
            time.sleep(0.02)
        # Limb was idled and resumed, never restarted: the same process throughout.
        assert rows['Limb']['restarts'] == 0 and rows['Limb']['status'] == ACTIVE
        assert rows['Limb']['pid'] == limb


def test_binary_that_cannot_start_is_retried_to_the_cap_without_harm(tmp_path, table) -> None:
    config, mappings = write_config(
        tmp_path, '<module name="Ghost" binary="no_such_package/ghost"/>' + worker('Fine'))
    with start_mcp(tmp_path, config, mappings, '-a', '-k', '2') as mcp:
        rows = table.until(lambda r: r['Ghost']['status'] == FAILED and
                           r['Fine']['status'] == ACTIVE, 'Ghost given up, Fine active')
        assert rows['Ghost']['restarts'] == 2 and rows['Fine']['restarts'] == 0
        wait_output(mcp, 'binary "no_such_package/ghost" of Ghost not found')
        wait_output(mcp, 'giving up on Ghost after 2 restarts')


def test_absurd_ttl_is_clamped_not_trusted(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Liar', extra='-t 86400'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        pid = table.until(active('Liar'), 'Liar active')['Liar']['pid']
        os.kill(pid, signal.SIGSTOP)
        # Trusting a day-long TTL would leave the hung module alone; the clamp (10 s) does not.
        table.until(lambda r: r['Liar']['status'] == ZOMBIE or r['Liar']['pid'] != pid,
                    'Liar found hung', timeout=40)
        assert wait_output(mcp, r'Liar announces TTL 86400\.0 s; using 10\.0 s')


def test_controller_and_turn_off(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('One') + worker('Two'))
    with start_mcp(tmp_path, config, mappings, '-a'):
        table.until(active('One', 'Two'), 'both active')
        listing = subprocess.run([sys.executable, find_executable('wurde_mcp', 'mcp_controller'),
                                  'status'], capture_output=True, text=True, timeout=60, check=True)
        one = next(line.split() for line in listing.stdout.splitlines() if line.startswith('One '))
        assert one[1:4] == ['ACTIVE', 'MANAGED', 'RUN']          # names, not numbers
        off = subprocess.run([sys.executable, find_executable('wurde_mcp', 'turn_off'), 'One'],
                             capture_output=True, text=True, timeout=60, check=True)
        assert 'quit One' in off.stdout
        rows = table.until(lambda r: r['One']['status'] == DEAD, 'One quit')
        assert rows['One']['restarts'] == 0 and rows['Two']['status'] == ACTIVE
        table.command(CMD_START, 'One')
        table.until(lambda r: r['One']['status'] == ACTIVE, 'One started again')
        table.command(CMD_STATE, 'Two', RunState.IDLE)
        table.until(lambda r: r['Two']['state'] == RunState.IDLE, 'Two idle')
        table.command(CMD_STOP, 'Two')
        table.until(lambda r: r['Two']['status'] == DEAD, 'Two stopped')
        bad = subprocess.run([sys.executable, find_executable('wurde_mcp', 'mcp_controller'),
                              'state', 'One', 'SLEEPY'], capture_output=True, text=True,
                             timeout=60, check=False)
        assert bad.returncode == 2 and 'unknown state SLEEPY' in bad.stderr


def test_mcp_killed_by_sigkill_leaves_no_orphans(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Child1') + worker('Child2'))
    mcp = start_mcp(tmp_path, config, mappings, '-a')
    try:
        rows = table.until(active('Child1', 'Child2'), 'children active')
        pids = [rows['Child1']['pid'], rows['Child2']['pid']]
        mcp.process.kill()
        deadline = time.monotonic() + 20
        while any(alive(pid) for pid in pids):
            assert time.monotonic() < deadline, f'orphans left: {pids}'
            time.sleep(0.05)
    finally:
        mcp.stop()


def test_sigterm_quits_and_reaps_every_module(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Tidy'))
    mcp = start_mcp(tmp_path, config, mappings, '-a')
    rows = table.until(active('Tidy'), 'Tidy active')
    mcp.process.terminate()
    assert mcp.process.wait(timeout=30) == 0
    mcp.stop()
    assert not alive(rows['Tidy']['pid'])
    assert 'exit code 0' in (tmp_path / 'mcp-modules' / 'Tidy.log').read_text()


@pytest.mark.process
def test_bad_configuration_is_refused_before_anything_starts(tmp_path) -> None:
    config, mappings = write_config(tmp_path, worker('Never'),
                                    '<connect module="A">\n<input interface="Foo" source="S"/>\n'
                                    '</connect>\n<connect module="B">\n<input '
                                    'interface="RangeFinder" source="S"/>\n</connect>')
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', config, '-m', mappings, '-a'],
                      env=dict(os.environ, WURDE_LOG_DIRECTORY=str(tmp_path))) as mcp:
        assert mcp.process.wait(timeout=60) == 1
    assert (f'{mappings}:7: mapping connects RangeFinder object "*" of module "B" to stream "S", '
            f'which the mapping at {mappings}:4 uses as Foo') in mcp.stderr
    assert not (tmp_path / 'mcp-modules' / 'Never.log').exists()


@pytest.mark.process
def test_mapping_against_what_the_supplier_reports_is_refused_at_configure(tmp_path) -> None:
    """The registration pass learns that Sup supplies Sup_out as Foo; a mapping that takes it
    as a RangeFinder is refused with its file, its line and both types."""
    config, mappings = write_config(tmp_path, worker('Sup'),
                                    '<connect module="Reader">\n<input interface="RangeFinder" '
                                    'source="Sup_out" object="Laser"/>\n</connect>')
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', config, '-m', mappings, '-a'],
                      env=dict(os.environ, WURDE_LOG_DIRECTORY=str(tmp_path))) as mcp:
        assert mcp.process.wait(timeout=90) == 1
    assert (f'{mappings}:4: mapping connects RangeFinder object "Laser" of module "Reader" to '
            'stream "Sup_out", but module "Sup" supplies that stream as Foo') in mcp.stderr
