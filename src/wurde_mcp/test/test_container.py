"""A ``<container>`` (issue 39) end to end: two counting modules in one process under a real MCP,
each in a thread of its own or, with ``scheduling="cooperative"``, both tasks of one hub thread.

One module's work raises: the MCP restarts it in the same container, it takes up its count, and
the other module — its pid, its count — goes on untouched.  Then the container process is
SIGKILLed: the MCP starts a new container with both modules, each taking up its count.
"""

from __future__ import annotations

import os
import pathlib
import signal
import time

import pytest
from mcp_fixture import HERE, Table, alive, start_mcp, wait_file, write_config
from wurde_core import StatusMode
from wurde_core.interfaces import Foo

ACTIVE = StatusMode.ACTIVE


#: A cooperative container's module reports this plus its start's number as its pid
#: (wurde_mcp.container.host.COOPERATIVE_PID_BASE).
COOPERATIVE_PID_BASE = 1 << 30


def _container_of(tid: int, mcp_pid: int) -> int:
    """The process (thread group) a module thread belongs to; for a task of a cooperative
    container (a pid above any process's), the container process the MCP runs."""
    if tid >= COOPERATIVE_PID_BASE:
        boxes = [int(p.name) for p in pathlib.Path('/proc').iterdir()
                 if p.name.isdigit() and _is_container(p, mcp_pid)]
        assert len(boxes) == 1, f'one container process of the MCP, not {boxes}'
        return boxes[0]
    for line in pathlib.Path(f'/proc/{tid}/status').read_text().splitlines():
        if line.startswith('Tgid:'):
            return int(line.split()[1])
    raise AssertionError(f'no Tgid for {tid}')


def _is_container(process: pathlib.Path, mcp_pid: int) -> bool:
    """Whether ``process`` is a live container program started by the MCP ``mcp_pid``."""
    try:
        argv = (process / 'cmdline').read_bytes().split(b'\0')
        fields = (process / 'stat').read_text().rsplit(')', 1)[1].split()
    except OSError:
        return False
    return fields[0] != 'Z' and int(fields[1]) == mcp_pid and any(a.endswith(b'/container') for a in argv)


class Counts:
    """Every count the two modules supplied, in order, read in the table's process."""

    def __init__(self, table: Table, names: tuple[str, ...]) -> None:
        self.table = table
        self.streams = {}
        for name in names:
            stream = Foo(f'{name}_count')
            stream.set_queue_mode(True)
            table.manager.register_consumer(stream)
            self.streams[name] = stream
        self.seen: dict[str, list[int]] = {name: [] for name in names}

    def take(self) -> None:
        for name, stream in self.streams.items():
            while stream.get_next_data():
                self.seen[name].append(int(stream.data.ranges[0]))

    def until(self, predicate, what: str, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while True:
            self.table.manager.step()
            self.take()
            if predicate(self.seen):
                return
            assert time.monotonic() < deadline, f'{what} not within {timeout} s: {self.seen}'
            self.table.manager.wait(0.05)

    def mark(self) -> dict[str, int]:
        """How many counts of each module have been read so far."""
        self.take()
        return {name: len(values) for name, values in self.seen.items()}


def _restarted(rows, name: str, restarts: int, old_pid: int) -> bool:
    row = rows.get(name)
    return bool(row) and row['restarts'] == restarts and row['status'] == ACTIVE and row['pid'] != old_pid


@pytest.mark.parametrize('scheduling', ['threads', 'cooperative'])
def test_a_module_that_raises_and_a_killed_container_come_back_with_their_state(
        ros_domain: int, tmp_path: pathlib.Path, table: Table, scheduling: str) -> None:
    fail = tmp_path / 'fail-A'
    modules = (f'<container name="box" scheduling="{scheduling}">\n'
               f'  <module name="CountA"><binary>counter_module:main</binary><options>-n CountA -f {fail}</options>'
               f'</module>\n'
               f'  <module name="CountB"><binary>counter_module:main</binary><options>-n CountB</options></module>\n'
               f'</container>')
    config, mappings = write_config(tmp_path, modules)
    env = {'PYTHONPATH': os.pathsep.join([str(HERE), os.environ.get('PYTHONPATH', '')])}
    counts = Counts(table, ('CountA', 'CountB'))
    with start_mcp(tmp_path, config, mappings, '-a', env=env) as mcp:
        rows = table.until(lambda r: all(r.get(n, {}).get('status') == ACTIVE for n in ('CountA', 'CountB')),
                           'both modules active')
        a_tid, b_tid = rows['CountA']['pid'], rows['CountB']['pid']
        box = _container_of(a_tid, mcp.process.pid)
        assert box == _container_of(b_tid, mcp.process.pid) != a_tid != b_tid, 'two modules of one process'
        assert b'container' in pathlib.Path(f'/proc/{box}/cmdline').read_bytes()
        names = {t.name: (t / 'comm').read_text().strip() for t in pathlib.Path(f'/proc/{box}/task').iterdir()}
        if scheduling == 'threads':
            # Each module's thread carries its name for top -H, ps -L and bench/footprint.py.
            assert [names[str(tid)] for tid in (a_tid, b_tid)] == ['CountA', 'CountB']
        else:
            # Both are tasks of the hub's thread; no thread of their own.
            assert min(a_tid, b_tid) > COOPERATIVE_PID_BASE
            assert 'hub-box' in names.values() and not {'CountA', 'CountB'} & set(names.values()), names
        counts.until(lambda seen: min(map(len, seen.values())) >= 5, 'five counts of each')

        # CountA's work raises: restarted inside the same container, from its saved count.
        before = counts.mark()
        fail.write_text('')
        rows = table.until(lambda r: _restarted(r, 'CountA', 1, a_tid), 'CountA restarted after raising')
        assert rows['CountB']['pid'] == b_tid and rows['CountB']['restarts'] == 0
        assert _container_of(rows['CountA']['pid'], mcp.process.pid) == box, 'restarted in the same container'
        wait_file(tmp_path / 'mcp-modules' / 'box.log', 'RuntimeError: CountA: told to fail')
        wait_file(tmp_path / 'mcp-modules' / 'CountA.log', 'exit code 1')
        counts.until(lambda seen: len(seen['CountA']) >= before['CountA'] + 10, 'CountA counting again')
        a_values = counts.seen['CountA']
        drop = [(x, y) for x, y in zip(a_values, a_values[1:]) if y <= x]
        assert not drop, f'CountA started its count again instead of taking it up: {drop}'
        b_values = counts.seen['CountB']
        assert all(y == x + 1 for x, y in zip(b_values, b_values[1:])), 'CountB went on without a break'

        # The container dies: a new one runs both modules, each from its saved count.
        a_tid = rows['CountA']['pid']
        before = counts.mark()
        os.kill(box, signal.SIGKILL)
        rows = table.until(lambda r: _restarted(r, 'CountA', 2, a_tid) and _restarted(r, 'CountB', 1, b_tid),
                           'both modules back in a new container')
        new_box = _container_of(rows['CountA']['pid'], mcp.process.pid)
        assert new_box == _container_of(rows['CountB']['pid'], mcp.process.pid) != box
        counts.until(lambda seen: all(len(seen[n]) >= before[n] + 5 for n in seen), 'both counting again')
        for name, values in counts.seen.items():
            drop = [(x, y) for x, y in zip(values, values[1:]) if y <= x]
            assert not drop, f'{name} started its count again after the container died: {drop}'
        assert mcp.stop() == 0
    assert not alive(new_box), 'the container ended with the MCP'
