"""What a contained module owns (issue 39): in a thread with a ModuleContext, the MCP's variables,
the pid, the role configuration and the logger are the module's; outside one, the process's."""

from __future__ import annotations

import os
import pathlib
import threading
from typing import Any

from wurde_core import CommsManager, RoleConfiguration, RunState, module_context
from wurde_core.enums import ProcessType
from wurde_core.heartbeat import MANAGED_ENV, RESTART_ENV, managed_state, restart_count
from wurde_core.logger import ModuleLogger, global_logger
from wurde_core.resume import STATE_ENV, state_path
from wurde_core.role_config import global_configuration, set_global_configuration


def _in_module(context: module_context.ModuleContext, work: Any) -> Any:
    """``work()`` run in a thread of its own inside ``context``, as the container runs a module."""
    result: dict[str, Any] = {}

    def run() -> None:
        module_context.enter(context)
        try:
            result['value'] = work()
        finally:
            module_context.leave()
    thread = threading.Thread(target=run)
    thread.start()
    thread.join(10.0)
    assert not thread.is_alive()
    return result['value']


def test_a_contained_module_reads_its_own_mcp_variables_and_reports_its_thread(monkeypatch) -> None:
    monkeypatch.setenv(RESTART_ENV, '0')
    monkeypatch.delenv(MANAGED_ENV, raising=False)
    context = module_context.ModuleContext('A', {RESTART_ENV: '3', MANAGED_ENV: 'CRITICAL',
                                                 STATE_ENV: '/data/A.resume'})
    seen = _in_module(context, lambda: (restart_count(), managed_state(), state_path(),
                                        module_context.process_id(), threading.get_native_id()))
    assert seen[:3] == (3, ProcessType.CRITICAL, pathlib.Path('/data/A.resume'))
    assert seen[3] == seen[4] == context.thread_id != os.getpid()
    # Outside the container's threads, the process's own.
    assert (restart_count(), managed_state(), module_context.process_id()) == (0, ProcessType.UNMANAGED,
                                                                              os.getpid())


def test_each_contained_module_has_its_own_configuration_and_logger() -> None:
    process_wide = global_configuration()
    a, b = module_context.ModuleContext('A'), module_context.ModuleContext('B')

    def configure(name: str) -> tuple[RoleConfiguration, RoleConfiguration, Any]:
        config = RoleConfiguration(name)
        set_global_configuration(config)
        logger = ModuleLogger(name, stderr=False, use_syslog=False)
        return config, global_configuration(), (logger, global_logger())

    config_a, seen_a, (logger_a, global_a) = _in_module(a, lambda: configure('A'))
    config_b, seen_b, (logger_b, global_b) = _in_module(b, lambda: configure('B'))
    assert seen_a is config_a and seen_b is config_b and config_a is not config_b
    assert global_a is logger_a and global_b is logger_b
    assert global_configuration() is process_wide, 'the modules left the process-wide one alone'
    assert global_logger() not in (logger_a, logger_b)


def test_a_quit_asked_before_the_manager_exists_is_kept_for_it() -> None:
    context = module_context.ModuleContext('A')
    context.request_quit()

    assert _in_module(context, lambda: CommsManager('A').state) == RunState.QUIT
