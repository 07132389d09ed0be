"""joystick_emulator: an emulated joystick on a FIFO, driven by commands on stdin or from a file.

``joystick_emulator -p /tmp/wurde-joystick`` makes the FIFO ``/tmp/wurde-joystick`` (the default,
which ``config/blind-teleop`` gives ``blind_teleop`` with ``-j``) and writes js_event records
into it as a kernel joystick would (:class:`~wurde_drivers.joystick.emulator.JoystickEmulator`):
init events to every program that opens it, then each change.  Commands
(:mod:`~wurde_drivers.joystick.script`) come one per line on stdin, or from ``-f FILE``; axis and
button names are those of the joystick config (``-c``, default ``joystick-config.xml`` in the
config directory; without one only numbers are understood).  At the end of the input the
joystick keeps its state until the program is told to quit.

Options: ``-p PATH``, ``-c FILE``, ``-J NAME`` (which ``<joystick>`` of the config; default the
first), ``-f FILE`` (a script: checked whole before anything is sent, a bad line ends the program
with status 2 and ``file:line: reason``), ``-a N`` / ``-b N`` (axes and buttons; default 8 and 12,
or more if the config names higher numbers).  The program is a WURDE module (heartbeat only), so
the MCP can run it too.
"""

from __future__ import annotations

import os
import pathlib
import select
import sys
import time

from wurde_core import CommsManager, Logger, RunState
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_idl.errors import ConfigError

from ..errors import DriverError
from .config import JoystickLayout, layout_named, load_joystick_config
from .emulator import JoystickEmulator
from .script import Command, ScriptError, parse_command

__all__ = ['main']

HELP = """  -p PATH  the FIFO to write (default /tmp/wurde-joystick)
  -c FILE  joystick-config.xml for axis and button names (default: <config dir>/joystick-config.xml)
  -J NAME  the <joystick> of the config to use (default: the first)
  -f FILE  read commands from FILE instead of stdin
  -a N     number of axes (default 8)
  -b N     number of buttons (default 12)
commands, one per line: axis NAME|N VALUE, button NAME|N 0|1, press NAME|N, release NAME|N,
  wait SECONDS, wait-reader, quit"""


class _Source:
    """Where commands come from: a checked script, or stdin read without blocking."""

    def __init__(self, layout: JoystickLayout, script: list[Command] | None) -> None:
        self.layout = layout
        self.script = script
        self._buffer = b''
        self._line = 0
        self._eof = script is not None
        self._fd = sys.stdin.fileno() if script is None and sys.stdin is not None else -1

    def next(self) -> Command | None:
        if self.script is not None:
            return self.script.pop(0) if self.script else None
        while True:
            if b'\n' in self._buffer or (self._eof and self._buffer):
                raw, _, self._buffer = self._buffer.partition(b'\n')
                self._line += 1
                try:
                    command = parse_command(raw.decode(errors='replace'), self.layout)
                except ScriptError as error:
                    print(f'joystick_emulator: stdin:{self._line}: {error}', file=sys.stderr, flush=True)
                    continue
                if command is not None:
                    return command
                continue
            if self._eof or self._fd < 0 or not select.select([self._fd], [], [], 0)[0]:
                return None
            data = os.read(self._fd, 4096)
            if not data:
                self._eof = True
            self._buffer += data


class _Player:
    """One turn of the program's loop: tell who opened or closed the joystick, then carry out
    commands until one waits (or there are none for now)."""

    def __init__(self, manager: CommsManager, emulator: JoystickEmulator, source: _Source) -> None:
        self.manager = manager
        self.emulator = emulator
        self.source = source
        self.seen = (0, 0)              # readers greeted, readers gone
        self.until = 0.0                # a ``wait`` ends then (monotonic)
        self.for_reader = False         # a ``wait-reader`` is on

    def step(self) -> None:
        emulator, name = self.emulator, self.manager.name
        if emulator.error is not None:
            raise SystemExit(f'joystick_emulator: the emulator failed: {emulator.error!r}')
        if emulator.connections > self.seen[0]:
            print(f'{name}: reader {emulator.connections} opened the joystick', flush=True)
        if emulator.disconnects > self.seen[1]:
            print(f'{name}: reader {emulator.disconnects} closed it', flush=True)
        self.seen = (emulator.connections, emulator.disconnects)
        while time.monotonic() >= self.until and not (self.for_reader and not emulator.connected):
            self.for_reader = False
            command = self.source.next()
            if command is None or not self._do(command):
                return

    def _do(self, command: Command) -> bool:
        """Carry out ``command``; False when the loop must stop taking commands."""
        try:
            if command.verb == 'axis':
                self.emulator.set_axis(command.number, int(command.value))
            elif command.verb == 'button':
                self.emulator.set_button(command.number, bool(command.value))
        except ValueError as error:       # a number beyond the joystick's axes or buttons
            print(f'joystick_emulator: {error}', file=sys.stderr, flush=True)
        if command.verb == 'wait':
            self.until = time.monotonic() + command.value
        elif command.verb == 'wait-reader':
            self.for_reader = True
        elif command.verb == 'quit':
            self.manager.set_state(RunState.QUIT)
            return False
        return True

    def close(self) -> None:
        self.emulator.wait_sent(1.0)
        self.emulator.stop()


def _load_script(path: str, layout: JoystickLayout) -> list[Command]:
    commands: list[Command] = []
    for number, line in enumerate(pathlib.Path(path).read_text().splitlines(), start=1):
        try:
            command = parse_command(line, layout)
        except ScriptError as error:
            raise ConfigError(path, number, str(error)) from None
        if command is not None:
            commands.append(command)
    return commands


def _count(text: str | None, default: int, least: int, what: str) -> int:
    try:
        count = int(text) if text is not None else default
    except ValueError:
        count = -1
    if not 1 <= count <= 256:
        print(f'joystick_emulator: -{what} {text!r} is not a count of 1 to 256', file=sys.stderr)
        raise SystemExit(2)
    return max(count, least)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('JoystickEmulator')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'p:c:J:f:a:b:').user
    path = config_file(manager, user.get('c'), 'joystick-config.xml')
    try:
        if user.get('c') or os.path.exists(path):
            layout = layout_named(load_joystick_config(path), user.get('J'))
        else:
            layout = JoystickLayout('numbers only', {}, {})
        script = _load_script(user['f'], layout) if 'f' in user else None
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except OSError as error:
        print(f'joystick_emulator: {error}', file=sys.stderr, flush=True)
        return 2
    axes = _count(user.get('a'), 8, max(layout.axes.values(), default=-1) + 1, 'a')
    buttons = _count(user.get('b'), 12, max(layout.buttons.values(), default=-1) + 1, 'b')
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    set_loop(manager, 0.02)
    emulator = JoystickEmulator(user.get('p', '/tmp/wurde-joystick'), axes=axes, buttons=buttons)
    try:
        emulator.start()
    except (OSError, DriverError) as error:     # a path that is there and is not a FIFO
        print(f'joystick_emulator: {error}', file=sys.stderr, flush=True)
        manager.clean_up()
        return 1
    print(f'{manager.name}: joystick "{layout.name}" ({axes} axes, {buttons} buttons) on '
          f'{emulator.path}', flush=True)
    player = _Player(manager, emulator, _Source(layout, script))
    return run_loop(manager, player.step, player.close)


if __name__ == '__main__':
    sys.exit(main())
