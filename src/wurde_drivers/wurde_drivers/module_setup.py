"""What every driver and dummy module does the same way: find its config file, refuse bad ones,
announce its loop.  Nothing here knows the simulator (real drivers never import it)."""

from __future__ import annotations

import os
import pathlib
import sys
from collections.abc import Callable, Sequence

from wurde_core import CommsManager, RunState
from wurde_idl.errors import ConfigError

from .xml_config import Device, device_named

__all__ = ['MODULE_TTL_S', 'config_file', 'configured_device', 'exit_on_config_error', 'run_loop',
           'set_loop']


def config_file(manager: CommsManager, given: str | None, default_name: str) -> str:
    """``-c`` if given, else ``default_name`` in the role configuration's config directory
    (``WURDE_CONFIG_DIR``), as the SICKServer's ``-c`` (WURDE 7.5)."""
    if given:
        return given
    return str(pathlib.Path(manager.config.get_config_directory()) / default_name)


def exit_on_config_error(program: str, error: ConfigError) -> int:
    """Print ``program: file:line: reason`` and return the exit status of a refused config (2)."""
    print(f'{os.path.basename(program)}: {error}', file=sys.stderr, flush=True)
    return 2


#: Heartbeat TTL of the device modules: their loops are short (milliseconds), but a TTL of twice
#: that would make a busy machine's scheduling look like a hang to the MCP.
MODULE_TTL_S = 1.0


def set_loop(manager: CommsManager, sleep_s: float, ttl_s: float = MODULE_TTL_S) -> None:
    """Sleep ``sleep_s`` per loop but announce a heartbeat TTL of ``ttl_s``."""
    manager.set_sleep_only(sleep_s)
    manager.set_heartbeat_only(ttl_s)


def configured_device(manager: CommsManager, argv: list[str], file_name: str,
                      load: Callable[[str], Sequence[Device]]) -> Device:
    """Parse the options and return the ``<device>`` of the config named like the module.

    ``-c FILE`` names the config (default ``file_name`` in the config directory) and ``-n`` the
    module, which picks its device by name (WURDE 7.5). A bad config ends the program with status
    2 and ``file:line: reason`` on stderr.
    """
    manager.set_help_string(f'  -c FILE  {file_name} (default: <config dir>/{file_name})\n'
                            '  -n NAME  the module and stream name; picks the <device> by name')
    opts = manager.parse_options(argv, 'c:')
    path = config_file(manager, opts.user.get('c'), file_name)
    try:
        return device_named(load(path), manager.name, path=path)
    except ConfigError as error:
        raise SystemExit(exit_on_config_error(argv[0], error)) from None


def run_loop(manager: CommsManager, step: Callable[[], None], close: Callable[[], None]) -> int:
    """The guide's loop for a device module: ``step()`` while in Run (``run_update`` keeps the
    module alive through Idle), then ``close()`` the device and clean up, also on an exception.
    Returns the exit status (0)."""
    try:
        while manager.run_update() == RunState.RUN:
            step()
    finally:
        try:
            close()
        finally:
            manager.clean_up()
    return 0
