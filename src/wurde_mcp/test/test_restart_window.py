"""The MCP's give-up rule on the supervisor itself (real CommsManager, no processes): ``-k``
restarts within :data:`~wurde_mcp.supervisor.RESTART_WINDOW_S` end in FAILED, however many a
long run has had before, and the back-off counts only the recent ones. The decisions take the
time as an argument, so the minute passes here without waiting for it."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from mcp_fixture import worker, write_config
from wurde_core import CommsManager, StatusMode
from wurde_mcp.config import read_mcp_config, read_mcp_mappings
from wurde_mcp.supervisor import BACKOFF_S, RESTART_WINDOW_S, Module, Supervisor


@pytest.fixture
def supervisor(tmp_path, ros_domain: int) -> Iterator[Supervisor]:
    config_path, mappings_path = write_config(tmp_path, worker('Flaky'))
    config = read_mcp_mappings(mappings_path, read_mcp_config(config_path))
    manager = CommsManager('RestartWindowTest')
    manager.set_no_heartbeat()
    watched = Supervisor(manager, config, log_directory=str(tmp_path), max_restarts=3)
    try:
        yield watched
    finally:
        watched.close()
        manager.clean_up()


def died(supervisor: Supervisor, module: Module, now: float) -> float | None:
    """What the supervisor decides when ``module`` dies at ``now``: the restart's delay, or None
    when it gives up."""
    module.wanted = True
    supervisor._schedule_restart(module, now)
    if module.status == StatusMode.FAILED:
        return None
    assert module.restart_at is not None
    return module.restart_at - now


def test_deaths_spread_over_a_long_run_are_restarted_every_time(supervisor: Supervisor) -> None:
    module = supervisor.modules['Flaky']
    # Ten deaths, each more than the window after the last: far more than -k 3 in all.
    delays = [died(supervisor, module, i * (RESTART_WINDOW_S + 1.0)) for i in range(10)]
    assert delays == [BACKOFF_S[0]] * 10
    assert module.restarts == 10 and module.status != StatusMode.FAILED


def test_k_restarts_within_the_window_give_up_with_back_off_on_the_recent_ones(
        supervisor: Supervisor) -> None:
    module = supervisor.modules['Flaky']
    assert died(supervisor, module, 0.0) == BACKOFF_S[0]
    later = RESTART_WINDOW_S + 5.0          # the first restart is out of the window now
    assert [died(supervisor, module, later + t) for t in (0.0, 1.0, 2.0)] == list(BACKOFF_S[:3])
    assert died(supervisor, module, later + 3.0) is None
    assert module.status == StatusMode.FAILED and not module.wanted and module.restarts == 4
