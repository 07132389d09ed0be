"""A running MCP for end-to-end tests, and a client that reads its module table."""

from __future__ import annotations

import os
import pathlib
import re
import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, RunState, StatusMode
from wurde_core.interfaces import robot_object_class
from wurde_testing import ChildProcess, find_executable

HERE = pathlib.Path(__file__).resolve().parent
WORKER = str(HERE / 'worker.py')


def write_config(directory: pathlib.Path, modules: str, mappings: str = '') -> tuple[str, str]:
    config = directory / 'mcp-config.xml'
    config.write_text(f'<?xml version="1.0"?>\n<mcp-config>\n{modules}\n</mcp-config>\n')
    mapping = directory / 'mcp-mappings.xml'
    mapping.write_text(f'<?xml version="1.0"?>\n<mcp-mappings>\n{mappings}\n</mcp-mappings>\n')
    return str(config), str(mapping)


def worker(name: str, managed: str = 'managed', extra: str = '') -> str:
    """A module entry running worker.py as ``name``."""
    return (f'<module name="{name}" binary="{WORKER}" managed="{managed}">'
            f'<options>-n {name} {extra}</options></module>')


def listener_script(directory: pathlib.Path) -> pathlib.Path:
    """``directory/listener.py``: module Listener, whose STRAT_ASSIGNED Foo consumer ``BarClient``
    prints ``VALUE <source> <ranges[0]>`` for every message (queue mode)."""
    script = directory / 'listener.py'
    script.write_text(
        '#!/usr/bin/env python3\n'
        'import sys\n'
        'from wurde_core import CommsManager, ConnectionStrategy, RunState\n'
        'from wurde_core.interfaces import Foo\n'
        'm = CommsManager("Listener"); m.parse_options(sys.argv); m.set_sleep(0.1)\n'
        'foo = Foo(ConnectionStrategy.ASSIGNED, "BarClient"); foo.set_queue_mode(True)\n'
        'm.register_consumer(foo)\n'
        'while m.run_update() != RunState.QUIT:\n'
        '    while foo.get_next_data():\n'
        '        print("VALUE", foo.data.source, foo.data.ranges[0], flush=True)\n'
        'm.clean_up()\n')
    script.chmod(0o755)
    return script


def start_mcp(directory: pathlib.Path, config: str, mappings: str, *args: str,
              env: dict[str, str] | None = None) -> ChildProcess:
    env = dict(os.environ, WURDE_LOG_DIRECTORY=str(directory), **(env or {}))
    mcp = ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', config, '-m', mappings, *args],
                       env=env)
    mcp.expect('MCP ready', timeout=60)
    return mcp


class Table:
    """Reads the MCP's module table (SimpleControl data on mcp_control) from this process."""

    def __init__(self, stream: str = 'mcp_control') -> None:
        self.manager = CommsManager('Tester')
        self.manager.set_no_sleep()
        self.control = robot_object_class('SimpleControl')(stream)
        # Every table, not the newest: a short state (a module Idle while a critical one restarts)
        # must not be missed by a test process that a loaded machine let fall behind.
        self.control.set_queue_mode(True)
        self.manager.register_consumer(self.control)
        self.rows: dict[str, dict[str, Any]] = {}

    def take(self) -> list[dict[str, dict[str, Any]]]:
        """Every table that arrived since the last call, oldest first."""
        self.manager.step()
        tables = []
        while self.control.get_next_data():
            d = self.control.data
            self.rows = {n: dict(status=StatusMode(s), state=RunState(r), pid=p, restarts=k)
                         for n, s, r, p, k in zip(d.module_names, d.module_status,
                                                  d.module_state, d.module_pid,
                                                  d.module_restarts)}
            tables.append(self.rows)
        return tables

    def refresh(self) -> dict[str, dict[str, Any]]:
        """The newest table."""
        self.take()
        return self.rows

    def until(self, predicate: Callable[[dict[str, dict[str, Any]]], bool], what: str,
              timeout: float = 60.0) -> dict[str, dict[str, Any]]:
        """The first table (in the order they came) for which ``predicate`` holds."""
        deadline = time.monotonic() + timeout
        while True:
            for rows in self.take():
                if rows and predicate(rows):
                    return rows
            rows = self.rows
            if time.monotonic() > deadline:
                raise AssertionError(f'{what} not reached within {timeout} s; table: {rows}')
            self.manager.wait(0.05)

    def command(self, command: int, module: str = '', state: RunState = RunState.RUN) -> None:
        deadline = time.monotonic() + 20
        while not self.control.peers():
            assert time.monotonic() < deadline, 'MCP control channel not matched'
            self.manager.step()
            self.manager.wait(0.05)
        requests = self.control.requests
        requests.command.set_value(command)
        requests.module.set_value(module)
        requests.state.set_value(state)
        self.control.publish_request()

    def heartbeat_info(self, module: str, timeout: float = 30.0) -> Any:
        """The process description a module publishes on its heartbeat's info channel."""
        heartbeat = robot_object_class('Heartbeat')(f'heartbeat/{module}')
        self.manager.register_consumer(heartbeat)
        deadline = time.monotonic() + timeout
        while not heartbeat.get_next_info():
            assert time.monotonic() < deadline, f'no heartbeat info from {module}'
            self.manager.step()
            self.manager.wait(0.05)
        return heartbeat.info

    def close(self) -> None:
        self.manager.clean_up()


def alive(pid: int) -> bool:
    """Whether ``pid`` is a live (not zombie) process."""
    try:
        with open(f'/proc/{pid}/stat') as handle:
            return handle.read().rsplit(')', 1)[1].split()[0] != 'Z'
    except (FileNotFoundError, ProcessLookupError):
        return False


def wait_output(child: ChildProcess, pattern: str, timeout: float = 30.0,
                since: float | None = None) -> re.Match[str]:
    """Wait (up to ``timeout`` s) for a line of the child's output matching ``pattern`` (with
    ``since``: one whose group ``at``, a monotonic time, is later than ``since``).

    :raises AssertionError: with the child's output when none comes in time.
    """
    regex = re.compile(pattern)
    deadline = time.monotonic() + timeout
    while True:
        for line in (child.stderr + child.stdout).splitlines():
            match = regex.search(line)
            if match and (since is None or float(match['at']) > since):
                return match
        if time.monotonic() > deadline:
            raise AssertionError(f'no line matching {pattern!r} within {timeout} s\n'
                                 f'stdout:\n{child.stdout}\nstderr:\n{child.stderr}')
        time.sleep(0.02)  # polls the reader threads' buffers; the deadline bounds it


def wait_file(path: pathlib.Path, text: str, timeout: float = 30.0) -> None:
    """Wait (up to ``timeout`` s) for ``text`` to appear in the file at ``path``."""
    deadline = time.monotonic() + timeout
    while not (path.exists() and text in path.read_text()):
        if time.monotonic() > deadline:
            raise AssertionError(f'{text!r} not in {path} within {timeout} s:\n'
                                 f'{path.read_text() if path.exists() else "(no file)"}')
        time.sleep(0.02)


#: What the MCP logs when it sees an exit or a zombie, with its monotonic time of noticing.
NOTICED = r'MCP: {name} (?:exited with code (?P<code>-?\d+)|missed its TTL).*noticed at monotonic (?P<at>[0-9.]+)'
