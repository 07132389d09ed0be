"""What every shipped module does the same way: find its config file, refuse a bad one, announce
its loop and run the guide's loop (5.2.1).  Drivers, dummies and the Pluto modules share it.  A
few programs keep a loop of their own, each for a reason: the guide's FooServer and FooClient (its
printed examples), emulator_host (ends with status 1 when its emulator fails), the dummy base and
wrist (catch-up stepping with Idle/Run hooks), tour and pose_i (interactive) and the MCP."""

from __future__ import annotations

import os
import pathlib
import sys
from collections.abc import Callable

from wurde_idl.errors import ConfigError

from .comms_manager import CommsManager
from .enums import RunState

__all__ = ['MODULE_TTL_S', 'config_file', 'exit_on_config_error', 'run_loop', 'set_loop']

#: Heartbeat TTL of modules with short loops (milliseconds): a TTL of twice the loop would make a
#: busy machine's scheduling look like a hang to the MCP.
MODULE_TTL_S = 1.0


def config_file(manager: CommsManager, given: str | None, default_name: str) -> str:
    """The module's config file, as the SICKServer's ``-c`` finds it (WURDE 7.5).

    :param manager: the module's manager, after ``parse_options`` (its configuration's config
        directory, ``WURDE_CONFIG_DIR``, is used).
    :param given: the file an option named (``-c``), or None/empty: ``default_name`` in the config
        directory.  A relative one that does not exist from the working directory but does in
        the config directory is taken from there.
    :param default_name: the file name used without ``given``.
    """
    directory = pathlib.Path(manager.config.get_config_directory())
    if given:
        path = pathlib.Path(given)
        if not path.is_absolute() and not path.exists() and (directory / path).exists():
            return str(directory / path)
        return given
    return str(directory / default_name)


def exit_on_config_error(program: str, error: ConfigError) -> int:
    """Print ``program: file:line: reason`` on stderr and return the exit status of a refused
    config (2).

    :param program: the program's path (``sys.argv[0]``); its base name is printed.
    :param error: the refusal.
    """
    print(f'{os.path.basename(program)}: {error}', file=sys.stderr, flush=True)
    return 2


def set_loop(manager: CommsManager, sleep_s: float, ttl_s: float = MODULE_TTL_S) -> None:
    """Sleep ``sleep_s`` per loop but announce a heartbeat TTL of ``ttl_s``.

    :param manager: the module's manager.
    :param sleep_s: seconds slept in each ``run_update``.
    :param ttl_s: the heartbeat TTL, seconds.
    """
    manager.set_sleep_only(sleep_s)
    manager.set_heartbeat_only(ttl_s)


def run_loop(manager: CommsManager, step: Callable[[], object], close: Callable[[], None]) -> int:
    """The guide's loop: ``step()`` while in Run (``run_update`` keeps the module alive through
    Idle), then ``close()`` the device and clean up, also on an exception.

    :param manager: the module's manager, its objects registered.
    :param step: one turn of the module's work; its result is ignored.
    :param close: releases the module's device; runs once, after the loop.
    :returns: the exit status (0): the program ends after it (``clean_up(exiting=True)``).
    """
    try:
        while manager.run_update() == RunState.RUN:
            step()
    finally:
        try:
            close()
        finally:
            manager.clean_up(exiting=True)
    return 0
