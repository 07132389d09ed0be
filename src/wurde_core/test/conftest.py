"""Fixtures for wurde_core tests: a manager in this process and peer modules in others."""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable, Iterator

import pytest

from wurde_core import CommsManager
from wurde_testing import ChildProcess

pytest_plugins = ['wurde_testing.fixtures']

HERE = pathlib.Path(__file__).parent


class Peer(ChildProcess):
    """A peer module (peer.py) in its own process, driven by commands."""

    def cmd(self, line: str, timeout: float = 20.0) -> str:
        """Run one command; return its result text (raises on ERR or timeout)."""
        self.send(line)
        answer = self.expect(line, timeout)
        while not (answer.startswith(f'OK {line}') or answer.startswith(f'ERR {line}')):
            answer = self.expect(line, timeout)
        if answer.startswith('ERR'):
            raise AssertionError(answer)
        return answer[len(f'OK {line}'):].strip()


@pytest.fixture
def peer(ros_domain: int) -> Iterator[Callable[..., Peer]]:
    """Start peer modules: ``peer('Name', *options)``; all are stopped after the test."""
    started: list[Peer] = []

    def start(name: str, *options: str) -> Peer:
        process = Peer([str(HERE / 'peer.py'), name, *options])
        started.append(process)
        process.expect('STATE RUN')
        return process

    yield start
    for process in started:
        process.stop()


@pytest.fixture
def manager(ros_domain: int) -> Iterator[CommsManager]:
    """A CommsManager named Tester in this process (no sleeping), cleaned up afterwards."""
    manager = CommsManager('Tester')
    manager.set_no_sleep()
    try:
        yield manager
    finally:
        manager.clean_up()


@pytest.fixture
def other(ros_domain: int) -> Iterator[CommsManager]:
    """A second CommsManager in this process (no sleeping, no heartbeat): the far end of a
    stream, or a controller commanding the ``manager`` fixture's states."""
    second = CommsManager('Other')
    second.set_no_sleep()
    second.set_no_heartbeat()
    try:
        yield second
    finally:
        second.clean_up()


def until(manager: CommsManager, predicate: Callable[[], bool], timeout: float = 20.0,
          what: str = 'condition') -> None:
    """Step ``manager`` until ``predicate()`` holds; fail after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        manager.step()
        if predicate():
            return
        if time.monotonic() > deadline:
            raise AssertionError(f'{what} not reached within {timeout} s')
        manager.wait(0.05)
