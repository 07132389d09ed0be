"""The shipped modules of the simulated Pluto live through Idle under the MCP (guide 5.2.1, 6.1).

With ``config/sim`` under the MCP: a lifecycle deactivate → activate keeps every module's PID,
nothing is published while a module is Idle and data flows again after; a SIGKILL of the critical
PlutoBase leaves every other module's PID unchanged, and they stay Idle until the base is back in
Run.  Data events are ordered by their DDS source timestamps (the writer's clock when it wrote)
and descriptions by their publish stamps; every process here shares the machine's clock, so
"nothing while Idle" is checked exactly, with no guessed time window: no data written between a
module's Idle description and the moment the MCP is told to activate (or, after the kill, the
restarted base's first description in Run).
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import signal
import time
from collections.abc import Callable
from typing import Any

import pytest
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.executors import SingleThreadedExecutor
from sim_fixture import sim_config
from wurde_core import CommsManager, RunState, StatusMode
from wurde_core.interfaces import robot_object_class
from wurde_core.naming import topic
from wurde_core.qos import stream_qos
from wurde_core.ros_adaptor import take_stamped
from wurde_testing import ChildProcess, find_executable
from wurde_testing.lifecycle import change_state

#: Module → one data stream it publishes continuously, and that stream's interface.
STREAMS = {'PlutoBase': ('PlutoBaseMotion', 'Egomotion'), 'PlutoLaser': ('PlutoLaser', 'RangeFinder'),
           'PlutoWrist': ('PlutoWrist', 'ActuatorState'), 'PlutoDMU': ('PlutoDMU', 'DMUState'),
           'PlutoGPS': ('PlutoGPS', 'GPS')}
WAIT_S = 90.0


@dataclasses.dataclass(frozen=True)
class _Description:
    state: int
    pid: int


class Watcher:
    """Records every module's heartbeat descriptions and one data stream each, with source stamps."""

    def __init__(self) -> None:
        self.manager = CommsManager('IdleWatcher')
        self.manager.set_no_sleep()
        self.manager.set_no_heartbeat()
        self.rows: dict[str, tuple[StatusMode, RunState]] = {}
        self.table_idle: dict[str, int] = {}
        self.table = robot_object_class('SimpleControl')('mcp_control')
        self.manager.register_consumer(self.table)
        node = self.manager.node
        heartbeat = robot_object_class('Heartbeat')
        self.subscriptions: dict[tuple[str, str], Any] = {}
        self.events: dict[tuple[str, str], list[tuple[Any, int]]] = {}
        #: Each module's heartbeat, consumed as the MCP does (queue mode: every description).
        self.heartbeats = {}
        for module, (stream, interface) in STREAMS.items():
            kind = robot_object_class(interface)
            self.heartbeats[module] = heartbeat(f'heartbeat/{module}')
            self.heartbeats[module].set_queue_mode(True)
            self.manager.register_consumer(self.heartbeats[module])
            self.events[(module, 'info')] = []
            self._add((module, 'beat'), heartbeat.data_type, topic(f'heartbeat/{module}', 'data'),
                      stream_qos(True))
            self._add((module, 'data'), kind.data_type, topic(stream, 'data'), stream_qos(True))
        self.change = node.create_client(ChangeState, '/MCP/change_state')
        self.get = node.create_client(GetState, '/MCP/get_state')
        self.executor = SingleThreadedExecutor(context=self.manager.context)
        self.executor.add_node(node)

    def _add(self, key: tuple[str, str], msg_type: type, name: str, qos: Any) -> None:
        self.subscriptions[key] = self.manager.node.create_subscription(msg_type, name,
                                                                        lambda _m: None, qos)
        self.events[key] = []

    def take(self) -> None:
        self.manager.step()
        for key, subscription in self.subscriptions.items():
            self.events[key].extend(take_stamped(subscription))
        # A description is stamped when the module publishes it (auto-timestamp, the module's
        # wall clock, as the DDS source timestamps of its data are).
        for module, heartbeat in self.heartbeats.items():
            while heartbeat.get_next_info():
                info = heartbeat.info
                self.events[(module, 'info')].append(
                    (_Description(info.state.get_value(), info.pid.get_value()),
                     info.timestamp.get_microseconds() * 1000))

    def until(self, predicate: Callable[[], bool], what: str) -> None:
        deadline = time.monotonic() + WAIT_S
        while True:
            self.take()
            if predicate():
                return
            if time.monotonic() > deadline:
                self.refresh_table()
                raise AssertionError(f'{what}: not within {WAIT_S} s; the MCP\'s table: '
                                     f'{self.rows}')
            self.manager.wait(0.02)

    def states(self, module: str, after: int = 0) -> list[tuple[int, int, int]]:
        """(state, pid, source stamp) of the module's descriptions written after ``after``."""
        return [(m.state, m.pid, s) for m, s in self.events[(module, 'info')] if s > after]

    def first(self, module: str, state: RunState, after: int = 0, pid: int | None = None) -> int | None:
        for value, described_pid, stamp in self.states(module, after):
            if value == state and (pid is None or described_pid == pid):
                return stamp
        return None

    def data_after(self, module: str, after: int) -> int:
        return sum(s > after for _, s in self.events[(module, 'data')])

    def beats_after(self, module: str, after: int) -> int:
        return sum(s > after for _, s in self.events[(module, 'beat')])

    def written_between(self, module: str, start: int, end: int) -> list[int]:
        return [s for _, s in self.events[(module, 'data')] if start < s < end]

    def spin(self, timeout: float) -> None:
        """Run the lifecycle clients' callbacks, taking the data meanwhile."""
        self.executor.spin_once(timeout_sec=timeout)
        self.take()

    def transition(self, transition_id: int, goal: str) -> None:
        assert change_state(self.spin, self.change, self.get, transition_id, goal, WAIT_S)

    def refresh_table(self) -> dict[str, tuple[StatusMode, RunState]]:
        """The MCP's newest module table; notes when it first shows each module Idle."""
        while self.table.get_next_data():
            data = self.table.data
            self.rows = {n: (StatusMode(s), RunState(r)) for n, s, r in zip(
                data.module_names, data.module_status, data.module_state)}
            now = time.time_ns()
            for name, (_, state) in self.rows.items():
                if state == RunState.IDLE:
                    self.table_idle.setdefault(name, now)
        return self.rows

    def all_active(self) -> bool:
        """Whether the MCP's module table shows every module ACTIVE and in Run."""
        rows = self.refresh_table()
        return all(rows.get(m) == (StatusMode.ACTIVE, RunState.RUN) for m in STREAMS)

    def forget_idle(self) -> int:
        """Start looking for Idle afresh (a module may have been Idle before, while the critical
        base was not up yet at start); returns the moment from which descriptions count."""
        self.refresh_table()
        self.table_idle.clear()
        return time.time_ns()

    def idle_since(self, module: str, after: int) -> int | None:
        """When the module is known to have been Idle since ``after``: its first Idle
        description written after it, or else the moment the MCP's table (which reports the
        module's own descriptions) first showed it Idle since :meth:`forget_idle` — later than
        the truth, so a check against it is never stricter than the truth.  (A test-side
        subscriber was seen, rarely and under load, to miss a description the MCP received.)"""
        return self.first(module, RunState.IDLE, after) or self.table_idle.get(module)

    def pids(self) -> dict[str, int]:
        """Each module's pid, from its newest description."""
        return {module: self.states(module)[-1][1] for module in STREAMS}

    def close(self) -> None:
        self.executor.remove_node(self.manager.node)
        self.manager.clean_up()


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.fixture
def robot(ros_domain: int, tmp_path: pathlib.Path):  # type: ignore[no-untyped-def]
    sim_config(tmp_path)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    watcher = Watcher()
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=WAIT_S)
            watcher.until(lambda: watcher.all_active() and all(
                watcher.first(m, RunState.RUN) and watcher.data_after(m, 0) >= 2 for m in STREAMS),
                'every module active in Run in the MCP\'s table, with data flowing')
            yield watcher, mcp
    finally:
        watcher.close()


def test_deactivate_then_activate_keeps_every_pid_and_silences_data_while_idle(robot) -> None:
    watcher, _mcp = robot
    pids = watcher.pids()
    # Only this deactivation's Idle counts: a module started before the critical base was up
    # was Idle then (a two-lane fresh-clone run took that start-up Idle for this one).
    asked = watcher.forget_idle()
    watcher.transition(Transition.TRANSITION_DEACTIVATE, 'inactive')
    watcher.until(lambda: watcher.refresh_table() is not None
                  and all(watcher.idle_since(m, asked) for m in STREAMS), 'every module Idle')
    idle = {m: watcher.idle_since(m, asked) for m in STREAMS}
    # Alive while Idle: every module goes on beating.
    watcher.until(lambda: all(watcher.beats_after(m, idle[m]) >= 2 for m in STREAMS),
                  'heartbeats from every idle module')
    activated = time.time_ns()  # nobody is told to Run before this
    watcher.transition(Transition.TRANSITION_ACTIVATE, 'active')
    watcher.until(lambda: watcher.all_active() and all(watcher.data_after(m, activated) >= 1
                                                       for m in STREAMS),
                  'every module in Run again, with data flowing')
    for module in STREAMS:
        assert watcher.written_between(module, idle[module], activated) == [], module
        assert watcher.pids()[module] == pids[module] and _alive(pids[module]), module
    # The wrist's states carry its simulated time (scale 1: the wall's, in 10 ms steps).  It
    # stood still while Idle, so what it writes after is dated after it was told to Run: no
    # burst of states back-dated into the Idle span, as a catch-up of the skipped steps wrote.
    stamps = [m.header.stamp.sec * 10 ** 9 + m.header.stamp.nanosec
              for m, s in watcher.events[('PlutoWrist', 'data')] if s > activated]
    step_ns = 10 ** 7
    assert stamps and min(stamps) >= activated - step_ns, (min(stamps) - activated) / 1e9


def test_killing_the_critical_base_idles_the_others_until_it_runs_again(robot) -> None:
    watcher, mcp = robot
    pids = watcher.pids()
    killed_at = time.time_ns()
    os.kill(pids['PlutoBase'], signal.SIGKILL)
    others = [m for m in STREAMS if m != 'PlutoBase']
    watcher.until(lambda: all(watcher.first(m, RunState.IDLE, killed_at) for m in others),
                  'every other module Idle')

    def base_back() -> int | None:
        return next((stamp for state, pid, stamp in watcher.states('PlutoBase', killed_at)
                     if state == RunState.RUN and pid != pids['PlutoBase']), None)
    watcher.until(lambda: base_back() is not None, 'PlutoBase restarted and in Run')
    back = base_back()
    assert back is not None
    idle = {m: watcher.first(m, RunState.IDLE, killed_at) for m in others}
    watcher.until(lambda: watcher.all_active() and all(watcher.data_after(m, back) >= 1
                                                       for m in others),
                  'the others in Run again, with data flowing')
    for module in others:
        # Idle until the restarted base was in Run: nothing written in between.
        assert watcher.written_between(module, idle[module], back) == [], module
        assert watcher.pids()[module] == pids[module] and _alive(pids[module]), module
    assert mcp.process.poll() is None
