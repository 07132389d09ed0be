"""Processes for the Eye's tests: the pattern camera and the installed ``eye``."""

from __future__ import annotations

import os
import pathlib
from collections.abc import Sequence

from wurde_testing import ChildProcess, find_executable

HERE = pathlib.Path(__file__).resolve().parent


def pattern_camera(stream: str, encoding: str, rate: float = 10.0) -> ChildProcess:
    """The test camera (``pattern_supplier.py``) publishing on ``stream`` in ``encoding``."""
    return ChildProcess([str(HERE / 'pattern_supplier.py'), '-i', stream, '-e', encoding,
                         '-f', str(rate)])


def eye(args: Sequence[str], *, display: str | None) -> ChildProcess:
    """The installed ``eye`` with ``args``; ``DISPLAY`` set to ``display`` or removed."""
    env = {k: v for k, v in os.environ.items() if k != 'DISPLAY'}
    if display is not None:
        env['DISPLAY'] = display
    return ChildProcess([find_executable('wurde_drivers', 'eye'), *args], env=env)


def status(observer: object, stream: str = 'Eye') -> object | None:
    """The latest ImageDisplay data an :class:`~sim_fixture.Observer` has seen, or None."""
    events = observer.events[stream]  # type: ignore[attr-defined]
    return events[-1][1] if events else None
