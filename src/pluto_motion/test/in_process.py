"""Helpers for in-process tests of a module: a Logger that keeps its lines, and a rig that steps
the module on its own CommsManager beside a second manager supplying its inputs over real DDS."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, Logger


class Said(Logger):
    """The module's Logger (named ``name``), keeping what it was told to log in :attr:`lines`."""

    def __init__(self, name: str) -> None:
        super().__init__(name, stderr=False, use_syslog=False)
        self.lines: list[str] = []

    def log(self, level: int | str, message: str) -> bool:
        self.lines.append(message)
        return super().log(level, message)


class ModuleRig:
    """A module under test (:attr:`module`, with a ``step()``) on :attr:`manager`, its inputs
    supplied by :attr:`peer`; subclasses set the three and may :meth:`feed` each turn."""

    manager: CommsManager
    peer: CommsManager
    module: Any

    def feed(self) -> None:
        """Publish what the peer sends every turn (nothing by default)."""

    def turn(self) -> None:
        self.feed()
        self.peer.step()
        self.manager.step()
        self.module.step()
        self.manager.wait(0.02)

    def until(self, predicate: Callable[[], bool], what: str, timeout: float = 60.0) -> None:
        """Turn until ``predicate()`` holds; fail after ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while not predicate():
            assert time.monotonic() < deadline, f'{what}: not within {timeout} s'
            self.turn()
