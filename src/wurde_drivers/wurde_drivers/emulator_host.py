"""Run a device emulator as a program: a pty at a fixed path, supervised like any module.

``sick_emulator -p /tmp/wurde/ttySICK`` (and the other ``*_emulator`` programs) start the device's
emulator on a pseudo-terminal and link it to the path given with ``-p`` (``-l`` is WURDE's standard
"list capabilities") (default
``/tmp/wurde-<device>``), so a device config can name that path as its port — as ``socat``'s
``link=`` does — and a user can try a driver and its config without the hardware. The program is
a WURDE module (heartbeat only), so the MCP starts, watches and stops it like the driver itself.
"""

from __future__ import annotations

import os
import pathlib
import sys
from collections.abc import Callable

from wurde_core import CommsManager, Logger, RunState

from .ports.pty import PtyEmulator

__all__ = ['run_emulator']


def _link(target: str, link: pathlib.Path) -> None:
    link.parent.mkdir(parents=True, exist_ok=True)
    tmp = link.with_name(f'.{link.name}.{os.getpid()}')
    tmp.unlink(missing_ok=True)
    tmp.symlink_to(target)
    tmp.replace(link)   # atomic: a driver never sees a missing or half-made link


def run_emulator(device: str, make: Callable[[dict[str, str]], PtyEmulator], *, user_spec: str = '',
                 help_text: str = '', argv: list[str] | None = None) -> int:
    """Host the emulator ``make(options)`` returns until Quit; ``device`` names the default link."""
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager(f'{device.upper()}Emulator')
    manager.set_help_string(f'  -p PATH  link the emulated port here (default /tmp/wurde-{device})\n{help_text}')
    opts = manager.parse_options(argv, 'p:' + user_spec)
    link = pathlib.Path(opts.user.get('p', f'/tmp/wurde-{device}'))
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    manager.set_sleep_only(0.1)
    manager.set_heartbeat_only(1.0)
    emulator = make(opts.user)
    emulator.start()
    try:
        _link(emulator.path, link)
        logger.notice(f'emulated {device} on {emulator.path}, linked at {link}')
        print(f'{manager.name}: {device} emulator on {link} -> {emulator.path}', flush=True)
        while manager.run_update() == RunState.RUN:
            if emulator.error is not None:
                logger.error(f'emulator failed: {emulator.error!r}')
                return 1
    finally:
        if link.is_symlink() and os.readlink(link) == emulator.path:
            link.unlink()
        emulator.stop()
        manager.clean_up(exiting=True)
    return 0
