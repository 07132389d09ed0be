"""A module process is owned by one thread: exit seen at once, escalation in the background."""

from __future__ import annotations

import pathlib
import signal
import time

import pytest
from wurde_mcp.clock import SupervisionClock
from wurde_mcp.process import ModuleProcess

from mcp_fixture import wait_file

STUBBORN = ['/bin/sh', '-c', 'trap "echo got INT" INT; trap "echo got TERM" TERM; '
            'echo ready; while :; do sleep 0.01; done']


@pytest.mark.process
def test_stop_escalates_in_the_background_to_sigkill(tmp_path: pathlib.Path) -> None:
    process = ModuleProcess('Stubborn', STUBBORN, str(tmp_path))
    try:
        # Its traps are set once it says so: a SIGINT before that (a loaded machine starts a
        # shell slowly) ends it at once, as it should, and there is nothing to escalate.
        wait_file(tmp_path / 'Stubborn.log', 'ready\n')
        started = time.monotonic()
        process.stop(step_s=0.3, grace_s=0.2)
        assert time.monotonic() - started < 0.1  # asking never waits for the escalation
        assert process.stopping() and process.poll() is None
        assert process.wait(10.0) == -signal.SIGKILL
        assert process.ended is not None and process.ended - started >= 0.2 + 2 * 0.3
    finally:
        process.signal(signal.SIGKILL)
        process.wait(10.0)
    log = (tmp_path / 'Stubborn.log').read_text()
    assert 'got INT' in log and 'got TERM' in log and log.endswith('--- exit code -9\n')
    # Each signal of the stop is said in the log with where the threads waited (a stuck module's
    # last words).
    said = [line.split()[1] for line in log.splitlines() if ' s after the stop was asked; its threads: ' in line]
    assert said == ['SIGINT', 'SIGTERM', 'SIGKILL'], log
    process.signal(signal.SIGKILL)  # after the end: a no-op, never a reused pid
    assert not process.stopping()


@pytest.mark.process
def test_exit_is_recorded_by_the_owner_without_polling(tmp_path: pathlib.Path) -> None:
    process = ModuleProcess('Quick', ['/bin/sh', '-c', 'exit 3'], str(tmp_path))
    assert process.wait(10.0) == 3
    assert process.poll() == 3 and not process.running()
    assert (tmp_path / 'Quick.log').read_text().endswith('--- exit code 3\n')


def test_supervision_clock_discounts_the_mcps_own_stalls() -> None:
    clock = SupervisionClock(max_gap_s=0.05, start=100.0)
    assert abs(clock.tick(100.01) - 0.01) < 1e-9 and abs(clock.tick(100.02) - 0.02) < 1e-9
    clock.tick(101.52)  # the MCP did not run for 1.5 s: that gap counts as 0.05 s
    assert abs(clock.now() - 0.07) < 1e-9
    assert clock.stalls == 1 and abs(clock.discounted_s - 1.45) < 1e-9
    assert abs(clock.longest_gap_s - 1.5) < 1e-9
    assert clock.steady_for(101.52) == 0.0  # the look that ends a stall starts a steady run
    clock.tick(101.53)
    assert abs(clock.steady_for(101.53) - 0.01) < 1e-9


SPAWNER = '''
import pathlib, sys, time
from wurde_mcp.process import ModuleProcess
log = pathlib.Path(sys.argv[1])
process = ModuleProcess("Child", ["/bin/sh", "-c", "echo ok$((6*7)); exec sleep 60"], str(log.parent))
deadline = time.monotonic() + 60
while "ok42" not in log.read_text():      # the shell ran (the start line has only its source)
    assert time.monotonic() < deadline
    time.sleep(0.01)
print(process.pid, flush=True)
sys.stdin.read()          # until the test lets go; then gone at once, as a SIGKILLed MCP is
import os; os._exit(0)
'''


@pytest.mark.process
def test_a_module_dies_with_the_process_that_started_it_and_has_its_own_group(tmp_path: pathlib.Path) -> None:
    """The launcher's PR_SET_PDEATHSIG (no Python between fork and exec in the MCP): the module,
    in its own process group, is killed by the kernel when its starter ends without a word."""
    import os
    import subprocess
    import sys
    spawner = subprocess.Popen([sys.executable, '-c', SPAWNER, str(tmp_path / 'Child.log')],
                               stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        pid = int(spawner.stdout.readline())
        assert os.getpgid(pid) == pid                      # its own group, set without preexec_fn
        assert b'prctl' not in open(f'/proc/{pid}/cmdline', 'rb').read()      # the module, not the launcher
        spawner.stdin.close()
        assert spawner.wait(timeout=60) == 0
        deadline = time.monotonic() + 30
        while os.path.exists(f'/proc/{pid}') and open(f'/proc/{pid}/stat').read().split()[2] != 'Z':
            assert time.monotonic() < deadline, f'the module {pid} outlived its starter'
            time.sleep(0.02)
    finally:
        spawner.kill()
        spawner.wait()
