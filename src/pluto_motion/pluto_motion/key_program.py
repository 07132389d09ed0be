"""What Pluto's keyboard programs share (Pluto 5: "each module has a simple user interface that
allows control from the keyboard ... xxx_i"): the terminal, the loop, ``q`` to quit, a help line
for an unknown key and a status line printed when it changes (:class:`Keys`, :func:`run_program`)
— for every program: the chain's ``drive_i``, ``avoid_i``, ``motion_i`` (:class:`KeyProgram`) and
``base_i``, ``wrist_i``, ``sick_i``, ``dmu_i``, ``gpsmeter``, ``slam_i``, ``local_i``.

The chain's programs: arrow keys change the speed: up/down by 0.1 m/s, left/right by 0.1 rad/s.
Each press starts from the link's status data[0..1], the velocities really commanded, not from the
last command sent: "By first reading the status the interface knows the working command value"
(Pluto 6.1) — after a timeout or
a stop a press continues from standstill.  The programs do not repeat commands, so the drive's
timeout stops a robot whose keyboard has gone quiet, as the seed intends.  Space stops, ``a``
starts the threads (start_activity), ``r`` releases the robot (cmdFlags -1), ``q`` stops and quits;
each program adds its link's own commands, some of which ask for numbers on a line of their own.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import IO, Any

from wurde_core import CommsManager, Logger, RunState
from wurde_core.module_loop import run_loop, set_loop

from .keyboard import Keyboard

__all__ = ['KeyProgram', 'Keys', 'run_program', 'step_velocity']

STEP_TV, STEP_RV = 0.1, 0.1
MAX_TV, MAX_RV = 1.0, 1.5
LOOP_S = 0.05
#: element[0] of every link's status (Pluto 6.1, 6.2).
CODES = {0: 'normal', -1: 'timeout', -10: 'thread stopped', 1: 'front bumper', 2: 'back bumper',
         3: 'sonar front', 4: 'sonar back', 5: 'sonar sides', 6: 'laser slow/stop', 7: 'laser fatal error'}
COMMON_KEYS = 'arrows drive, space stops, a start, r release, q quit'


def _clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, round(value, 3)))


def step_velocity(key: str, tv: float, rv: float) -> tuple[float, float]:
    """An arrow key's new (tv, rv) from the working ones: up/down 0.1 m/s, left/right 0.1 rad/s.

    :param key: ``up``, ``down``, ``left`` or ``right`` (any other changes nothing).
    :param tv: the working linear velocity (m/s), the link's status data[0].
    :param rv: the working angular velocity (rad/s), data[1].
    :returns: the new velocities, within ±1.0 m/s and ±1.5 rad/s.
    """
    tv += {'up': STEP_TV, 'down': -STEP_TV}.get(key, 0.0)
    rv += {'left': STEP_RV, 'right': -STEP_RV}.get(key, 0.0)
    return _clamp(tv, MAX_TV), _clamp(rv, MAX_RV)


class Keys:
    """A keyboard program's keys over its proxy (a :class:`pluto_motion.proxy.Proxy`): ``q``
    quits, the program's own keys (:meth:`act`), the help line for any other, and the status line
    (:meth:`status`) printed whenever it changes."""

    #: Keys of the program's own commands and what they do, for the help line.
    KEYS = ''

    def __init__(self, proxy: Any, ask: Callable[[str, int], list[float] | None], out: IO[str] = sys.stdout) -> None:
        """Keep the proxy; nothing is sent before :meth:`start`.

        :param proxy: the module's proxy (updated by :meth:`show_status`).
        :param ask: asks for numbers on a line of their own: ``ask(prompt, count)`` gives
            ``count`` numbers, or None when the user typed something else.
        :param out: where the program's lines are printed.
        """
        self.proxy, self.ask, self.out = proxy, ask, out
        self.shown = ''

    def say(self, text: str) -> None:
        """Print a line of the program.

        :param text: the line.
        """
        print(text, file=self.out, flush=True)

    def help_line(self) -> str:
        return f'keys: {self.KEYS + ", " if self.KEYS else ""}q quit'

    def act(self, key: str) -> bool:
        """The program's own keys; False when ``key`` is not one of them.

        :param key: the key's name as :class:`~pluto_motion.keyboard.Keyboard` gives it (``a``,
            ``up``, ``space`` ...).
        """
        return False

    def quit(self) -> None:
        """What to do before quitting (a device left at rest)."""

    def press(self, key: str) -> bool:
        """Act on ``key``; False on quit.

        :param key: the key's name as :class:`~pluto_motion.keyboard.Keyboard` gives it.
        """
        if key == 'q':
            self.quit()
            self.say('quit')
            return False
        if not self.act(key):
            self.say(self.help_line())
        return True

    def status(self) -> str:
        """The status line ('' when there is nothing to show yet)."""
        return ''

    def show_status(self) -> None:
        """Print the status when it changes."""
        self.proxy.update()
        text = self.status()
        if text and text != self.shown:
            self.shown = text
            self.say(text)

    def start(self) -> None:
        """At start, before the first key."""

    def close(self) -> None:
        """At the end, after the loop (a last command delivered)."""


class KeyProgram(Keys):
    """One chain link's keys over its proxy (a :class:`pluto_motion.chain_proxy.ChainProxy`)."""

    # -- what each link defines ------------------------------------------------------------------
    def velocity(self, tv: float, rv: float) -> str:
        """Send a velocity command; what to print about it.

        :param tv: the linear velocity (m/s).
        :param rv: the angular velocity (rad/s).
        """
        raise NotImplementedError

    def key(self, key: str, tv: float, rv: float) -> bool:
        """The link's own keys; False when ``key`` is not one of them.

        :param key: the key's name as :class:`~pluto_motion.keyboard.Keyboard` gives it.
        :param tv: the working linear velocity (m/s), from the link's status.
        :param rv: the working angular velocity (rad/s).
        """
        return False

    def describe(self) -> str:
        """The link's own part of the status line."""
        return ''

    # -- the common keys -------------------------------------------------------------------------
    def press(self, key: str) -> bool:
        """Act on ``key``; False on quit.

        :param key: the key's name as :class:`~pluto_motion.keyboard.Keyboard` gives it; the
            arrows, ``space``, ``a``, ``r`` and ``q`` are every link's, others :meth:`key`'s.
        """
        tv, rv = self.proxy.velocities or (0.0, 0.0)          # the working command (Pluto 6.1)
        if key in ('up', 'down', 'left', 'right'):
            tv, rv = step_velocity(key, tv, rv)
            self.say(f'command tv {tv:+.2f} m/s rv {rv:+.2f} rad/s{self.velocity(tv, rv)}')
        elif key == 'space':
            self.velocity(0.0, 0.0)
            self.say('command stop')
        elif key == 'a':
            self.proxy.start_activity()
            self.say('start_activity')
        elif key == 'r':
            self.proxy.release_robot()
            self.say('release_robot')
        elif key == 'q':
            self.velocity(0.0, 0.0)
            self.say('quit')
            return False
        elif not self.key(key, tv, rv):
            self.say(self.help_line())
        return True

    def help_line(self) -> str:
        return f'keys: {COMMON_KEYS}{", " + self.KEYS if self.KEYS else ""}'

    def start(self) -> None:
        self.proxy.start_activity()      # held until the link is matched, as every command

    def close(self) -> None:
        self.proxy.command.wait_delivered(1.0)      # the last stop reaches the link

    def show_status(self) -> None:
        """Print the status when it changes."""
        self.proxy.update()
        code = self.proxy.code
        if code is None:
            return
        tv, rv = self.proxy.velocities or (0.0, 0.0)
        text = f'status {code} ({CODES.get(code, "?")}) tv {tv:+.2f} rv {rv:+.2f}{self.describe()}'
        if text != self.shown:
            self.shown = text
            self.say(text)


def run_program(name: str, options: str, help_text: str,
                make: Callable[[CommsManager, dict[str, str], Callable[[str, int], list[float] | None]], Keys],
                argv: list[str] | None = None) -> int:
    """The keyboard program's main: options, the terminal in cbreak mode, the loop.

    :param name: the program's (manager's) name.
    :param options: its own options, in getopt form (``b:`` ...).
    :param help_text: the lines ``-h`` prints about them.
    :param make: makes the program from the manager, the parsed options and the number asker;
        a ValueError (a bad option value) ends the program with status 2.
    :param argv: the command line, the program's name first (None: ``sys.argv``).
    :returns: the exit status (2 without a terminal or for a bad option value).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager(name)
    manager.set_help_string(help_text)
    user = manager.parse_options(argv, options).user
    try:
        keyboard = Keyboard(sys.stdin)
    except OSError as error:
        print(f'{name}: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)

    def ask(prompt: str, count: int) -> list[float] | None:
        with keyboard.cooked():
            try:
                values = [float(v) for v in input(f'{prompt}: ').replace(',', ' ').split()]
            except (ValueError, EOFError):
                values = []
        if len(values) != count:
            print(f'{name}: {count} numbers wanted; nothing sent', flush=True)
            return None
        return values

    try:
        program = make(manager, user, ask)
    except ValueError as error:          # a bad option value
        print(f'{name}: {error}', file=sys.stderr, flush=True)
        manager.clean_up()
        return 2
    set_loop(manager, LOOP_S)
    print(program.help_line(), flush=True)
    program.start()

    def step() -> None:
        program.show_status()
        for key in keyboard.keys(0.0):
            if not program.press(key):
                manager.set_state(RunState.QUIT)
                break

    with keyboard:
        return run_loop(manager, step, program.close)
