"""The MCP executable: a WURDE module and a ROS 2 lifecycle node (seed: WURDE chapter 6).

``mcp -c mcp-config.xml -m mcp-mappings.xml`` (``ros2 run wurde_mcp mcp ...``), as the guide
types it (chapter 6), reads its files and starts the system: it configures and activates at once.
With ``--lifecycle`` it stays unconfigured and waits for the lifecycle transitions:

- configure: read the configuration and mappings (refusing bad ones with file, line and reason)
  and run the registration pass — each internal binary is started with ``-r`` and reports what it
  supplies and consumes;
- activate: start the internal modules and set every module to Run;
- deactivate: set every module to Idle;
- cleanup and shutdown: Quit every module and reap the internal ones.

``-a`` (configure and activate at once) is the default and still accepted.  Activation starts
every internal module the configuration lists (listing a module is asking for it; chapter 6's
daemon starts modules on request) and, from then on, a supplier a consumer asks for that is not
running (6.3).  ``-n NAME`` (or ``WURDE_MCP_NAME``) names the MCP when
several share a domain, one per host: its streams are then ``mcp/NAME`` and ``mcp_control/NAME``,
its modules are told its name, and it commands only its own (see ``Supervisor.owns``).  Transitions
are driven with the standard lifecycle
services (``/MCP/change_state``), so any ROS 2 lifecycle tool can drive the MCP.  The MCP is one
node, ``/MCP``: its CommsManager's node is the lifecycle node, and the manager's loop serves the
lifecycle services (no executor of its own).  Files come from
``-c`` / ``-m``, else the role configuration (WURDE_MCP_CONFIG, WURDE_MCP_MAPPINGS, ...).
"""

from __future__ import annotations

import os
import sys
import time
from typing import Any

from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn

from wurde_core import (CommsManager, ConfigError, RunState, StatusMode, g_error, g_info,
                        g_warn, global_configuration)
from wurde_core.heartbeat import mcp_name
from wurde_idl import load_all

from .config import McpConfig, read_mcp_config, read_mcp_mappings, validate
from .supervisor import MAX_RESTARTS, RESTART_WINDOW_S, Supervisor

#: How long the registration pass waits for the binaries started with -r.
REGISTRATION_TIMEOUT_S = 15.0
#: More for each module of the largest container: its modules start in one interpreter, taking
#: turns at its imports and its GIL (config/pluto-container's twelve ended 15 s apart on a quiet
#: 2-core machine, config/pluto's twelve processes 4 s apart).
CONTAINED_REGISTRATION_S = 2.5
#: Keeps the MCP unconfigured until a lifecycle transition (without it the MCP starts the system).
LIFECYCLE_FLAG = '--lifecycle'
#: The supervision loop's turn (s).  20 ms: at 10 ms the MCP took 5.2 % of one core driving
#: config/pluto, at 20 ms 3.2 % (issue 39, bench/footprint.py); a gap past the supervision clock's
#: 50 ms still means the MCP did not run, and bench/mcp_load.py still catches a SIGSTOP within
#: TTL + 0.3 s under load (1022 ms at most, TTL 1 s).
LOOP_S = 0.02


class McpNode(LifecycleNode):
    """The MCP's node (its CommsManager's): a lifecycle node whose transition callbacks are the
    :class:`Mcp`'s once one is attached (before that, every transition fails)."""

    def __init__(self, node_name: str, **kwargs: Any) -> None:
        self.mcp: Mcp | None = None
        super().__init__(node_name, enable_communication_interface=True, **kwargs)

    def _call(self, transition: str, state: LifecycleState) -> TransitionCallbackReturn:
        if self.mcp is None:
            return TransitionCallbackReturn.FAILURE
        return getattr(self.mcp, transition)(state)

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._call('on_configure', state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._call('on_activate', state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._call('on_deactivate', state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._call('on_cleanup', state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._call('on_shutdown', state)


class Mcp:
    """The MCP: lifecycle callbacks around a :class:`Supervisor`."""

    def __init__(self, manager: CommsManager, config_file: str, mappings_file: str,
                 max_restarts: int = MAX_RESTARTS) -> None:
        self.manager = manager
        self.max_restarts = max_restarts
        self.config_file = config_file
        self.mappings_file = mappings_file
        self.supervisor: Supervisor | None = None
        manager.step()  # opens the node
        if not isinstance(manager.node, McpNode):
            raise TypeError('the MCP needs CommsManager(..., node_type=McpNode)')
        self.node = manager.node
        self.node.mcp = self

    def load(self) -> McpConfig:
        """Read and check the configuration and mappings.

        :raises ConfigError: naming the file, the line and the reason.
        """
        config = read_mcp_config(self.config_file)
        if self.mappings_file and os.path.exists(self.mappings_file):
            read_mcp_mappings(self.mappings_file, config)
        elif self.mappings_file and self.mappings_file != self._default_mappings():
            raise ConfigError(self.mappings_file, None, 'cannot read: no such file')
        validate(config, load_all())
        return config

    @staticmethod
    def _default_mappings() -> str:
        return global_configuration().get_mcp_mappings_file()

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        try:
            config = self.load()
        except ConfigError as exc:
            g_error(f'MCP: {exc}')
            return TransitionCallbackReturn.FAILURE
        role = global_configuration()
        log_directory = os.path.join(role.get_log_directory(), 'mcp-modules')
        for warning in config.warnings:
            g_warn(f'MCP: {warning}')
        self.supervisor = Supervisor(self.manager, config, log_directory=log_directory,
                                     bin_directory=role.get_bin_directory(),
                                     max_restarts=self.max_restarts)
        try:
            self.registration_pass()
        except ConfigError as exc:
            g_error(f'MCP: {exc}')
            self.supervisor.quit_all(wait_s=2.0)
            self.supervisor.close()
            self.supervisor = None
            return TransitionCallbackReturn.FAILURE
        g_info(f'MCP: configured with {len(config.modules)} modules from {self.config_file}')
        return TransitionCallbackReturn.SUCCESS

    def registration_pass(self) -> None:
        """Start every internal binary with -r and take in the capability reports.

        :raises ConfigError: when a report contradicts a mapping (file, line, both types).
        """
        supervisor = self.supervisor
        assert supervisor is not None
        started = []
        supervisor.registering = True
        try:
            for module in supervisor.modules.values():
                if module.internal and supervisor.start(module.name, argv_extra=('-r',)):
                    module.wanted = False  # it is meant to exit: no restart
                    started.append(module)
            sizes = [sum(m.spec.container == c for m in supervisor.modules.values())
                     for c in supervisor.config.containers]
            deadline = time.monotonic() + REGISTRATION_TIMEOUT_S + CONTAINED_REGISTRATION_S * max(sizes, default=0)
            while time.monotonic() < deadline and any(
                    m.process is not None and m.process.running() for m in started):
                self.manager.step()
                supervisor.tick()
                self.manager.wait(0.02)
        finally:
            supervisor.registering = False
        for module in supervisor.modules.values():
            if module.process is not None:
                if module.process.running():
                    g_error(f'MCP: {module.name} did not finish its registration (-r) in time')
                module.process.stop_and_wait(step_s=1.0)
                module.process = None
            module.restarts = module.starts = 0     # the registration runs were not the module's
            module.recent_restarts = []
            module.restart_at = None
            module.status = StatusMode.UNKNOWN
        self.manager.step()
        supervisor.tick()
        conflicts = [reason for module in supervisor.modules.values()
                     for reason in supervisor.streams.check(module)]
        if conflicts:
            mapping, reason = conflicts[0]
            raise ConfigError(mapping.path, mapping.line, reason)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        assert self.supervisor is not None
        self.supervisor.start_all()
        self.supervisor.set_all(RunState.RUN)
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        assert self.supervisor is not None
        self.supervisor.set_all(RunState.IDLE)
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.quit_all()
        if self.supervisor is not None:
            self.supervisor.close()  # a later configure makes a new one
            self.supervisor = None
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.quit_all()
        return TransitionCallbackReturn.SUCCESS

    def quit_all(self) -> None:
        if self.supervisor is not None:
            self.supervisor.quit_all()

    def spin_once(self) -> None:
        """Supervise (the manager's loop serves the lifecycle services); never blocks."""
        if self.supervisor is not None:
            self.supervisor.tick()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    own_end = argv.index('--ros-args') if '--ros-args' in argv else len(argv)
    lifecycle = LIFECYCLE_FLAG in argv[1:own_end]      # a long option: not getopt's (5.1.1)
    argv = [a for i, a in enumerate(argv) if not (0 < i < own_end and a == LIFECYCLE_FLAG)]
    manager = CommsManager(mcp_name(), node_type=McpNode)
    manager.set_help_string('  -c FILE  MCP configuration (default: role config, mcp-config.xml)\n'
                            '  -m FILE  MCP mappings (default: role config, mcp-mapping.xml)\n'
                            '  -a       configure and activate at once (the default)\n'
                            f'  {LIFECYCLE_FLAG}  stay unconfigured: wait for lifecycle transitions '
                            '(/MCP/change_state)\n'
                            f'  -k N     restarts of a module within {RESTART_WINDOW_S:.0f} s before giving '
                            f'up (default {MAX_RESTARTS})')
    manager.parse_options(argv, 'c:m:ak:')
    role = global_configuration()
    config_file = role.get_option('c') if role.have_option('c') else role.get_mcp_config_file()
    mappings_file = role.get_option('m') if role.have_option('m') else \
        role.get_mcp_mappings_file()
    manager.set_sleep_only(LOOP_S)
    manager.set_heartbeat_only(0.5)
    manager.step()
    try:
        max_restarts = int(role.get_option('k')) if role.have_option('k') else MAX_RESTARTS
    except ValueError:
        print(f'mcp: -k needs a number, not {role.get_option("k")!r}', file=sys.stderr)
        return 2
    mcp = Mcp(manager, config_file, mappings_file, max_restarts)
    if role.have_option('a') and lifecycle:
        print(f'mcp: -a and {LIFECYCLE_FLAG} contradict each other', file=sys.stderr)
        manager.clean_up()
        return 2
    if not lifecycle:
        if mcp.node.trigger_configure() != TransitionCallbackReturn.SUCCESS \
                or mcp.supervisor is None:
            manager.clean_up()
            return 1
        mcp.node.trigger_activate()
    print('MCP ready', flush=True)
    try:
        while manager.run_update() != RunState.QUIT:
            if manager.state != RunState.RUN:
                manager.set_run()  # the MCP itself is not idled by anyone
            mcp.spin_once()
    finally:
        if mcp.supervisor is not None:
            g_info(mcp.supervisor.summary())
        mcp.quit_all()
        manager.clean_up(wait=False, exiting=True)  # its modules, its goodbye's readers, have ended
    return 0


if __name__ == '__main__':
    sys.exit(main())
