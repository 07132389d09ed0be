"""A module process is owned by one thread: exit seen at once, escalation in the background."""

from __future__ import annotations

import pathlib
import signal
import time

from wurde_mcp.clock import SupervisionClock
from wurde_mcp.process import ModuleProcess

STUBBORN = ['/bin/sh', '-c', 'trap "echo got INT" INT; trap "echo got TERM" TERM; '
            'echo ready; while :; do sleep 0.01; done']


def test_stop_escalates_in_the_background_to_sigkill(tmp_path: pathlib.Path) -> None:
    process = ModuleProcess('Stubborn', STUBBORN, str(tmp_path))
    try:
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
    process.signal(signal.SIGKILL)  # after the end: a no-op, never a reused pid
    assert not process.stopping()


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
