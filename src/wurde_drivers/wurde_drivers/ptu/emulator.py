"""A Directed Perception PTU-46 on a pseudo-terminal (docs/protocols.md 2; PTU-D46 manual 4.2-4.5).

The unit powers up as the manual shows it: echo on (``ED`` turns it off), verbose feedback
(``FT`` makes it terse), immediate execution (``I``; ``S`` slaves position commands until ``A``,
which answers when the move ends), independent speed control (``CI``; ``CV`` is pure velocity
control with signed speeds), position limits enforced (``LE``) at -3090..3090 pan and -907..604
tilt, and 185.1428 arc-seconds per position. The axes move on :meth:`tick` with trapezoidal
speed profiles (symmetric acceleration, manual 4.4.4). Error replies use the manual's words.

Choices where the manual is silent (documented so tests do not mistake them for facts):
``C`` answers ``i``/``p`` in terse mode (what Player's ``GetMode`` compares); entering ``CV``
zeroes the desired speeds so the unit does not start moving by itself; position commands are
accepted but ignored in ``CV``; ``H`` stops the axes at once; a reset takes ``reset_s`` seconds,
then prints ``!T!T!P!P*`` and leaves both axes at 0. Commands that arrive while ``A`` or ``R``
is pending are held and run afterwards.

Faults: :attr:`silent` (reads, never answers), :meth:`inject_garbage`, :meth:`inject_limit_hit`,
:meth:`corrupt_next` (replies replaced by garbage lines), and :meth:`unplug` / :meth:`replug`
(a power cycle on replug restores the power-on defaults).
"""

from __future__ import annotations

import dataclasses
import os
import threading
import time

from ..errors import CodecError
from ..motion import ramp_step
from ..ports.pty import PtyEmulator
from .codec import Error, LimitHit, Ok, Reply, ResetDone, decode_command, encode_reply

__all__ = ['Ptu46Emulator', 'PtuEmulator', 'VERSION']

VERSION = 'Pan-Tilt Controller v2.14.0, (C)2006 Directed Perception, Inc., All Rights Reserved'
#: The unit's lowest allowed lower speed bound (manual 4.4.6: ``PL20 ! Motor speed cannot be ...``).
HARD_LOWER_SPEED = 31
_DELIMITERS = b' \r\n\t'


@dataclasses.dataclass
class _Axis:
    """One axis in position units (pos, pos/s, pos/s^2)."""

    word: str                 # 'Pan' or 'Tilt', as in the messages
    minimum: int
    maximum: int
    resolution: float = 185.1428
    position: float = 0.0
    velocity: float = 0.0
    target: int = 0
    pending: int | None = None
    speed: int = 1000         # desired speed; signed in pure velocity mode
    saved_speed: int = 1000
    accel: int = 2000
    base: int = 1000
    upper: int = 2902
    lower: int = HARD_LOWER_SPEED

    @property
    def current(self) -> int:
        return int(round(self.position))

    def moving(self, velocity_mode: bool) -> bool:
        if velocity_mode:
            return self.velocity != 0.0
        return self.velocity != 0.0 or self.current != self.target

    def step(self, dt: float, velocity_mode: bool, enforce: bool) -> None:
        """Advance by ``dt`` seconds: toward the target along the shared trapezoidal profile
        (:func:`~wurde_drivers.motion.ramp_step`), or toward the speed in pure velocity mode."""
        accel = float(max(self.accel, 1))
        if velocity_mode:
            change = max(-accel * dt, min(accel * dt, float(self.speed) - self.velocity))
            self.velocity += change
            self.position += self.velocity * dt
        else:
            self.position, self.velocity = ramp_step(self.position, self.velocity, float(self.target),
                                                     float(abs(self.speed)), accel, dt)
        if enforce and not self.minimum <= self.position <= self.maximum:
            self.position = float(min(max(self.position, self.minimum), self.maximum))
            self.velocity = 0.0


class PtuEmulator(PtyEmulator):
    """A PTU-46 that a driver opens at ``path`` (9600 8N1)."""

    def __init__(self, *, reset_s: float = 0.0, tick_s: float = 0.005) -> None:
        """Open the pty and power up; :meth:`start` runs it.

        :param reset_s: seconds ``R`` takes before ``!T!T!P!P*`` is printed.
        :param tick_s: seconds between two turns of the emulator's thread, and the axes' motion step.
        """
        super().__init__(tick_s=tick_s)
        self.reset_s = reset_s
        #: Set: input is read but never echoed nor answered.
        self.silent = threading.Event()
        self.commands_seen = 0
        #: Every byte the driver wrote, for tests (the last 64 KiB).
        self.received = bytearray()
        self._corrupt = 0
        self._power_cycle = False
        self._held_replay = False
        self._power_on()

    # -- faults (called from the test thread) -------------------------------------------------
    def inject_garbage(self, data: bytes | None = None) -> None:
        """Write garbage to the driver.

        :param data: the bytes; None: 24 random bytes (no line end among them) and ``\\r\\n``.
        """
        self.write(data if data is not None else os.urandom(24).replace(b'\n', b'?') + b'\r\n')

    def inject_limit_hit(self, axis: str = 'pan') -> None:
        """Print an asynchronous ``!P`` (or ``!T``) as when an axis hits its limit.

        :param axis: ``'pan'``; anything else means tilt.
        """
        self.write(encode_reply(LimitHit('pan' if axis == 'pan' else 'tilt')))

    def corrupt_next(self, count: int = 1) -> None:
        """Replace the next ``count`` replies by garbage lines.

        :param count: how many; replaces any count still pending.
        """
        self._corrupt = count

    def unplug(self) -> None:
        self.unplugged.set()

    def replug(self, *, power_cycle: bool = True) -> None:
        """Come back after :meth:`unplug`.

        :param power_cycle: the unit was powered off and has forgotten every setting.
        """
        self._power_cycle = power_cycle
        self.unplugged.clear()

    # -- state for tests ----------------------------------------------------------------------
    @property
    def pan(self) -> int:
        return self._pan.current

    @property
    def tilt(self) -> int:
        return self._tilt.current

    @property
    def echo(self) -> bool:
        return self._echo

    @property
    def verbose(self) -> bool:
        return self._verbose

    @property
    def moving(self) -> bool:
        return any(axis.moving(self._velocity_mode) for axis in (self._pan, self._tilt))

    # -- protocol -------------------------------------------------------------------------------
    def _power_on(self) -> None:
        self._pan = _Axis('Pan', -3090, 3090)
        self._tilt = _Axis('Tilt', -907, 604)
        self._echo = True
        self._verbose = True
        self._slaved = False
        self._velocity_mode = False
        self._enforce = True
        self._line = bytearray()
        self._held = bytearray()
        self._awaiting = False
        self._reset_at: float | None = None
        self._last_tick: float | None = None
        self._unstepped = 0.0

    def _check_power(self) -> None:
        if self._power_cycle:
            self._power_cycle = False
            self._power_on()

    def on_bytes(self, data: bytes) -> None:
        """Echo and answer the commands in ``data`` (held while a command or a reset is under way).

        :param data: the bytes read from the pty, in any pieces.
        """
        self._check_power()
        if not self._held_replay:
            self.received += data
            del self.received[:-65536]
        if self.silent.is_set():
            return
        if self._awaiting or self._reset_at is not None:
            self._held += data
            return
        # A real unit reads its position when asked: after a stall of this thread on a loaded
        # machine, the axes are where the time says, not where the last tick left them (else a
        # query answered before the catch-up and the next one after it read a speed far too high).
        self._advance(time.monotonic())
        out = bytearray()
        for index in range(len(data)):
            byte = data[index:index + 1]
            if self._echo:
                out += byte
            if byte not in _DELIMITERS:
                self._line += byte
                if len(self._line) > 64:          # runaway input: the unit would complain
                    self._line.clear()
                    out += self._encode(Error('Illegal Command'))
                continue
            if not self._line:
                continue
            token, self._line = bytes(self._line), bytearray()
            reply = self._execute(token)
            if reply is not None:
                out += self._encode(reply)
            if self._awaiting or self._reset_at is not None:
                self._held += data[index + 1:]
                break
        if out:
            self.write(bytes(out))

    def _encode(self, reply: Reply) -> bytes:
        if self._corrupt > 0:
            self._corrupt -= 1
            return os.urandom(12).replace(b'\n', b'#') + b'\r\n'
        return encode_reply(reply)

    def tick(self, now: float) -> None:
        """Move the axes to ``now``; finish a reset, or answer an awaited move (``a``) that has ended.

        :param now: ``time.monotonic()`` of this turn.
        """
        self._check_power()
        self._advance(now)
        if self._reset_at is not None and now >= self._reset_at:
            self._reset_at = None
            self._recentre()
            self._finish(ResetDone())
        elif self._awaiting and not self.moving:
            self._awaiting = False
            self._finish(Ok())

    def _advance(self, now: float) -> None:
        """Move the axes on to ``now``.

        The motion profile stops exactly on the target only for steps of one length
        (wurde_drivers.motion); a late tick on a loaded machine would carry an axis past its
        target, which a real unit never does.  So time is spent in whole steps of tick_s (at most
        0.1 s at a time), the rest kept for the next call."""
        dt = 0.0 if self._last_tick is None else max(0.0, min(now - self._last_tick, 0.1))
        self._last_tick = now
        self._unstepped += dt
        while self._unstepped >= self.tick_s:
            self._unstepped -= self.tick_s
            for axis in (self._pan, self._tilt):
                axis.step(self.tick_s, self._velocity_mode, self._enforce)

    def _finish(self, reply: Reply) -> None:
        if not self.silent.is_set():
            self.write(self._encode(reply))
        held, self._held = bytes(self._held), bytearray()
        if held:
            self._held_replay = True
            try:
                self.on_bytes(held)
            finally:
                self._held_replay = False

    def _recentre(self) -> None:
        for axis in (self._pan, self._tilt):
            axis.position, axis.velocity, axis.target, axis.pending = 0.0, 0.0, 0, None

    # -- commands -------------------------------------------------------------------------------
    def _execute(self, token: bytes) -> Reply | None:
        self.commands_seen += 1
        try:
            command = decode_command(token)
        except CodecError:
            return Error('Illegal Command Argument')
        name = command.name
        if len(name) == 2 and name[0] in 'pt' and name[1] in 'ponxrsabul':
            return self._axis_command(self._pan if name[0] == 'p' else self._tilt, name[1],
                                      command.value)
        if command.value is not None:
            return Error('Illegal Command Argument' if name in _UNIT_COMMANDS else 'Illegal Command')
        if name not in _UNIT_COMMANDS:
            return Error('Illegal Command')
        return self._unit(name)

    def _axis_command(self, axis: _Axis, letter: str, value: int | None) -> Reply:
        """``P?``/``T?`` commands; ``letter`` is the second letter."""
        if letter in 'po':
            return self._position(axis, value, offset=letter == 'o')
        if letter == 's':
            return self._speed(axis, value)
        if letter in 'nx':
            word, limit = (('Minimum', axis.minimum) if letter == 'n' else ('Maximum', axis.maximum))
            return self._fixed(value, limit, f'{word} {axis.word} position is {limit}')
        if letter == 'r':
            return self._fixed(value, axis.resolution,
                               f'{axis.resolution} seconds arc per {axis.word} position')
        if letter == 'a':
            return self._query_or_set(axis, value, 'accel',
                                      '{word} acceleration is {value} positions/sec^2', 1, 100000)
        if letter == 'b':
            return self._query_or_set(axis, value, 'base',
                                      'Current {word} base speed is {value} positions/sec', 0,
                                      axis.upper)
        if letter == 'u':
            return self._query_or_set(axis, value, 'upper',
                                      'Maximum {word} speed is {value} positions/sec', axis.lower,
                                      10000)
        return self._query_or_set(axis, value, 'lower', 'Minimum {word} speed is {value} positions/sec',
                                  HARD_LOWER_SPEED, axis.upper,
                                  f'Motor speed cannot be less than {HARD_LOWER_SPEED} pos/sec')

    def _answer(self, terse: object, verbose: str) -> Ok:
        return Ok(verbose if self._verbose else str(terse))

    def _position(self, axis: _Axis, value: int | None, offset: bool) -> Reply:
        if value is None:
            return self._answer(axis.current, f'Current {axis.word} position is {axis.current}')
        wanted = axis.current + value if offset else value
        if self._enforce and wanted > axis.maximum:
            return Error(f'Maximum allowable {axis.word} position is {axis.maximum}')
        if self._enforce and wanted < axis.minimum:
            return Error(f'Minimum allowable {axis.word} position is {axis.minimum}')
        if not self._velocity_mode:
            if self._slaved:
                axis.pending = wanted
            else:
                axis.target = wanted
        return Ok()

    def _speed(self, axis: _Axis, value: int | None) -> Reply:
        if value is None:
            return self._answer(axis.speed, f'Desired {axis.word} speed is {axis.speed} positions/sec')
        if value < 0 and not self._velocity_mode:
            return Error('Illegal Command Argument')
        if abs(value) > axis.upper:
            return Error(f'{axis.word} speed cannot exceed {axis.upper} positions/sec')
        if abs(value) < axis.lower and not (value == 0 and self._velocity_mode):
            return Error(f'{axis.word} speed cannot be less than {axis.lower} positions/sec')
        axis.speed = value
        return Ok()

    def _query_or_set(self, axis: _Axis, value: int | None, field: str, verbose: str,
                      low: int, high: int, low_error: str | None = None) -> Reply:
        if value is None:
            current = getattr(axis, field)
            return self._answer(current, verbose.format(word=axis.word, value=current))
        if value < low and low_error is not None:
            return Error(low_error)
        if not low <= value <= high:
            return Error('Illegal Command Argument')
        setattr(axis, field, value)
        return Ok()

    def _fixed(self, value: int | None, terse: object, verbose: str) -> Reply:
        if value is not None:
            return Error('Illegal Command Argument')
        return self._answer(terse, verbose)

    def _halt(self, axes: tuple[_Axis, ...]) -> Reply:
        for axis in axes:
            axis.velocity, axis.pending = 0.0, None
            axis.target = axis.current
            axis.position = float(axis.current)
            if self._velocity_mode:
                axis.speed = 0
        return Ok()

    def _await(self) -> Reply | None:
        for axis in (self._pan, self._tilt):
            if axis.pending is not None:
                axis.target, axis.pending = axis.pending, None
        if self.moving:
            self._awaiting = True
            return None
        return Ok()

    def _reset(self) -> Reply | None:
        for axis in (self._pan, self._tilt):
            axis.velocity, axis.pending = 0.0, None
        if self.reset_s <= 0.0:
            self._recentre()
            return ResetDone()
        self._reset_at = time.monotonic() + self.reset_s
        return None

    def _control(self, velocity: bool) -> Reply:
        if velocity and not self._velocity_mode:
            for axis in (self._pan, self._tilt):
                axis.saved_speed, axis.speed = abs(axis.speed), 0
        elif not velocity and self._velocity_mode:
            for axis in (self._pan, self._tilt):
                axis.speed = max(axis.saved_speed, axis.lower)
                axis.target = axis.current
        self._velocity_mode = velocity
        return Ok()

    def _unit(self, name: str) -> Reply | None:
        """The commands that are not ``P?``/``T?``, all without argument."""
        if name in _FLAGS:
            attribute, setting = _FLAGS[name]
            setattr(self, attribute, setting)
            return Ok()
        if name == 'e':
            return self._answer('e' if self._echo else 'd',
                                f'Echoing is {"ON" if self._echo else "OFF"}')
        if name == 'f':
            return self._answer('v' if self._verbose else 't',
                                f'Feedback is {"VERBOSE" if self._verbose else "TERSE"}')
        if name == 'l':
            state = 'ENABLED (soft limits enabled)' if self._enforce else 'DISABLED'
            return self._answer('e' if self._enforce else 'd', f'Limit bounds are {state}')
        if name == 'c':
            mode = 'PURE VELOCITY' if self._velocity_mode else 'INDEPENDENT'
            return self._answer('p' if self._velocity_mode else 'i', f'Speed control mode is {mode}')
        if name in ('ci', 'cv'):
            return self._control(name == 'cv')
        if name == 'a':
            return self._await()
        if name in ('h', 'hp', 'ht'):
            axes = {'h': (self._pan, self._tilt), 'hp': (self._pan,), 'ht': (self._tilt,)}[name]
            return self._halt(axes)
        if name == 'r':
            return self._reset()
        if name == 'v':
            return Ok(VERSION)
        if name == 'df':
            self._power_on()
        return Ok()                                 # df, ds, dr


#: Commands that set one flag of the unit.
_FLAGS = {'ee': ('_echo', True), 'ed': ('_echo', False), 'fv': ('_verbose', True),
          'ft': ('_verbose', False), 'i': ('_slaved', False), 's': ('_slaved', True),
          'le': ('_enforce', True), 'ld': ('_enforce', False)}
_UNIT_COMMANDS = frozenset(_FLAGS) | {'e', 'f', 'l', 'c', 'ci', 'cv', 'a', 'h', 'hp', 'ht', 'r', 'v',
                                      'ds', 'dr', 'df'}


Ptu46Emulator = PtuEmulator  # old name (docs/naming.md)
