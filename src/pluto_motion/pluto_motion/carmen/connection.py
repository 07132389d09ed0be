"""CARMEN's IPC calls: ``carmen_ipc_initialize``, ``_dispatch``, ``_sleep``, ``_addPeriodicTimer``,
``_disconnect``, on the program's one :class:`~.ipc.CarmenIpc`.

CARMEN's interface functions are global (one IPC connection per process), so the connection made
by :func:`carmen_ipc_initialize` is the one every ``carmen_*`` call uses, as in C.  The robot's
streams are named at initialization (defaults: the simulated Pluto's); a WURDE module that
already has a CommsManager passes it and keeps its own loop settings.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

from wurde_core import CommsManager
from wurde_core.errors import NotRegisteredError

from .ipc import CarmenIpc, Timer, TimerHandler

__all__ = ['STREAMS', 'carmen_ipc_addPeriodicTimer', 'carmen_ipc_disconnect', 'carmen_ipc_dispatch',
           'carmen_ipc_initialize', 'carmen_ipc_sleep', 'connection']

#: The robot's streams by default: config/pluto's (and config/sim's) Pluto.
STREAMS = {'base': 'PlutoBase', 'frontlaser': 'PlutoLaser', 'rearlaser': 'PlutoRearLaser',
           'navigator': 'Navigator', 'map_server': 'MapServer'}

_current: list[CarmenIpc] = []


def connection() -> CarmenIpc:
    """The connection :func:`carmen_ipc_initialize` made.

    :raises NotRegisteredError: before it (CARMEN's calls need IPC initialized first).
    """
    if not _current or _current[0].closed:
        raise NotRegisteredError('CARMEN is not connected: call carmen_ipc_initialize(sys.argv) first')
    return _current[0]


def carmen_ipc_initialize(argv: Sequence[str], *, manager: CommsManager | None = None,
                          **streams: str) -> CarmenIpc:
    """Connect this program: a CommsManager named after ``argv[0]`` that parses ``argv`` (WURDE's
    options: ``-n NAME``, ``-h`` ...), unless ``manager`` is given.  ``streams`` overrides
    :data:`STREAMS` (``base='PlutoBase'``, ``frontlaser=...``, ``rearlaser``, ``navigator``,
    ``map_server``).

    :param argv: the program's command line, its name first (``sys.argv``); ignored when
        ``manager`` is given.
    :param manager: a WURDE module's own manager, which keeps its loop settings (None: a new one).
    :param streams: stream names that differ from :data:`STREAMS`, by key.
    :returns: the connection; a connection made before is closed.
    :raises TypeError: a stream key :data:`STREAMS` does not have.
    """
    unknown = set(streams) - set(STREAMS)
    if unknown:
        raise TypeError(f'carmen_ipc_initialize: unknown stream {", ".join(sorted(unknown))}; known: '
                        f'{", ".join(STREAMS)}')
    if _current and not _current[0].closed:
        _current[0].close()
    _current.clear()
    if manager is None:
        name = os.path.splitext(os.path.basename(argv[0]))[0] if argv else 'carmen'
        manager = CommsManager(name or 'carmen')
        manager.parse_options(list(argv))
        manager.set_no_sleep()               # the IPC calls wait on arrivals and timers themselves
    ipc = CarmenIpc(manager, {**STREAMS, **streams})
    _current.append(ipc)
    return ipc


def carmen_ipc_sleep(timeout: float) -> int:
    """Handle messages and timers for ``timeout`` seconds; 0, or -1 when the program is to quit
    (a signal, the MCP's Quit).

    :param timeout: how long (s), at least 0.
    :raises InvalidValueError: a negative or non-finite time.
    """
    return 0 if connection().sleep(timeout) else -1


def carmen_ipc_dispatch() -> None:
    """Handle messages and timers until the program is to quit (CARMEN's never returns; ours
    returns then, so that the program can end cleanly)."""
    connection().dispatch()


def carmen_ipc_addPeriodicTimer(interval: float, handler: TimerHandler, client_data: Any = None) -> Timer:  # noqa: N802
    """Call ``handler(client_data, now_ms, scheduled_ms)`` every ``interval`` seconds while
    messages are handled (IPC's TIMER_HANDLER_TYPE).

    :param interval: the period (s), above 0.
    :param handler: called with ``client_data`` and the times now and scheduled (monotonic ms).
    :param client_data: passed to the handler as it is.
    :returns: the timer (CARMEN returns nothing; ours can be kept and ignored).
    """
    return connection().add_timer(interval, handler, client_data)


def carmen_ipc_disconnect() -> None:
    """Release the streams and leave (idempotent)."""
    if _current:
        _current[0].close()
