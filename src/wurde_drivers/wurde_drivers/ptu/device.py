"""Device layer of the Directed Perception PTU-46 pan-tilt unit (docs/protocols.md 2; WURDE guide 7.4).

:class:`PtuDriver` speaks the unit's ASCII protocol over a :class:`~wurde_drivers.ports.serial_link.SerialLink`
(9600 8N1) and works in SI units: angles in rad (pan counter-clockwise positive, tilt up
positive, as the PTUnit interface says), speeds in rad/s, accelerations in rad/s^2. It converts
with the resolution the unit reports (``pr``/``tr``, arc-seconds per position).

Contract of the command methods (:meth:`set_position`, :meth:`set_speed`,
:meth:`set_acceleration`, :meth:`set_velocity_mode`, :meth:`halt`, :meth:`reset`,
:meth:`query`): each sends its command(s) and waits for every reply, at most ``reply_timeout``
seconds per reply (``reset_timeout`` for a reset). They return only when the unit said ``*``;
they raise :class:`~wurde_drivers.errors.DeviceError` carrying the unit's own message when it
answered ``! <message>``, and :class:`~wurde_drivers.errors.DeviceTimeout` when it did not
answer in time or is not there. After a timeout or a vanished port the next command first
redoes :meth:`connect` (the unit may have been power-cycled and lost its settings), so a caller
just retries. Asynchronous limit hits (``!P``/``!T``) that arrive while waiting are kept for
:meth:`poll`. The class is not thread-safe: one thread drives it.
"""

from __future__ import annotations

import dataclasses
import math
import time

from ..errors import DeviceError, DeviceTimeout
from ..ports.serial_link import LinkStats, SerialLink
from .codec import (Command, Error, LimitHit, Ok, PtuDeframer, Reply, ResetDone,
                          encode_command)

__all__ = ['BAUDRATE', 'Ptu46', 'PtuDriver', 'PtuEvent', 'PtuLimits', 'PtuState']

BAUDRATE = 9600
_ARCSEC = math.pi / (180.0 * 3600.0)
#: Player's initialisation (ptu46.cc): terse feedback, echo off, independent control, immediate.
_INIT = ('ft', 'ed', 'ci', 'i')
#: A velocity's interval is at least this many times the uncertainty of its two read instants
#: (10: the interval, and so the speed, is off by 10 % at most).
TIMING_MARGIN = 10.0
_LIMIT_QUERIES = ('pn', 'px', 'tn', 'tx', 'pl', 'pu', 'tl', 'tu')

PtuEvent = LimitHit | ResetDone


@dataclasses.dataclass(frozen=True)
class PtuLimits:
    """What the unit reported at connect, in rad, rad/s and rad per position step."""

    pan_min: float
    pan_max: float
    tilt_min: float
    tilt_max: float
    pan_speed_min: float
    pan_speed_max: float
    tilt_speed_min: float
    tilt_speed_max: float
    pan_resolution: float
    tilt_resolution: float


@dataclasses.dataclass(frozen=True)
class PtuState:
    """One :meth:`PtuDriver.query`: measured angles (rad), desired speeds (rad/s, signed in velocity
    mode), velocities estimated from this and the previous query (rad/s; 0 on the first one),
    whether an axis moves, and the monotonic time of the query."""

    pan: float
    tilt: float
    pan_speed: float
    tilt_speed: float
    pan_velocity: float
    tilt_velocity: float
    moving: bool
    stamp: float


class PtuDriver:
    """A PTU-46 on a serial link. Construct (no I/O), :meth:`connect`, command, :meth:`close`."""

    def __init__(self, link: SerialLink, *, reply_timeout: float = 1.0,
                 reset_timeout: float = 30.0, connect_timeout: float = 5.0) -> None:
        """Keep the settings; no I/O until :meth:`connect`.

        :param link: the port, at :data:`BAUDRATE`.
        :param reply_timeout: longest wait for one reply (s).
        :param reset_timeout: longest wait for the reset string after ``r`` (a real unit needs
            many seconds to recalibrate).
        :param connect_timeout: longest :meth:`connect` when a command reconnects by itself.
        """
        self.link = link
        self.reply_timeout = reply_timeout
        self.reset_timeout = reset_timeout
        self.connect_timeout = connect_timeout
        self._deframer = PtuDeframer()
        self._events: list[PtuEvent] = []
        self._raw: dict[str, float] = {}
        self._connected = False
        self._stale = True
        self._disconnects = 0
        self._velocity_mode = False
        self._targets = (0, 0)
        #: The velocity's reference sample: pan, tilt (positions), read instant and its lateness (s).
        self._last: tuple[float, float, float, float] | None = None
        #: Half the quickest pan query's round trip since connecting (s): what every read shares.
        self._least_spread = math.inf
        self._velocity = (0.0, 0.0)
        #: Replies that answered nothing (late replies after a timeout, stray ``*``).
        self.unsolicited = 0

    # -- life cycle ---------------------------------------------------------------------------
    @property
    def connected(self) -> bool:
        """True after a successful :meth:`connect` and until a timeout or a vanished port."""
        return self._connected and not self._stale

    @property
    def stats(self) -> LinkStats:
        return self.link.stats

    @property
    def bad_lines(self) -> int:
        """Reply lines dropped as garbage."""
        return self._deframer.bad_lines

    def connect(self, timeout: float = 5.0) -> None:
        """Initialise the unit as Player does and read its resolution and limits.

        Sends ``" "`` and, after reading away whatever the unit says for 0.1 s, ``ft ed ci i``;
        then queries ``pr tr pn px tn tx pl pu tl tu`` (and ``pp tp``). If those make no sense (a unit that lost
        its calibration), resets it (``r``, expecting ``!T!T!P!P*``) and asks again.

        :param timeout: the longest the whole initialisation may take, in seconds.
        :raises DeviceTimeout: the unit did not answer within ``timeout`` (or is not there).
        :raises DeviceError: it answered with an error or with values that make no sense.
        """
        deadline = time.monotonic() + timeout
        self._connected = False
        self._stale = True
        try:
            self.link.open()
        except DeviceError as error:
            raise DeviceTimeout(f'{self.link.url}: PTU not there: {error}') from error
        self._disconnects = self.link.stats.disconnects
        self.link.reset_input()
        self._deframer.reset()
        self._write(b' ')
        self._discard(min(0.1, max(0.0, deadline - time.monotonic())))
        for name in _INIT:
            self._exchange(Command(name), self._step(deadline))
        if not self._read_limits(deadline):
            self._exchange(Command('r'), min(deadline, time.monotonic() + self.reset_timeout),
                           ResetDone)
            if not self._read_limits(deadline):
                raise DeviceError(f'{self.link.url}: PTU reports no usable resolution and limits '
                                  f'after a reset: {self._raw}')
        self._velocity_mode = False
        self._targets = (round(self._query_number('pp', self._step(deadline))),
                         round(self._query_number('tp', self._step(deadline))))
        self._last, self._least_spread = None, math.inf
        self._connected = True
        self._stale = False

    def close(self) -> None:
        """Close the port (idempotent)."""
        self._connected = False
        self._stale = True
        self.link.close()

    # -- limits ---------------------------------------------------------------------------------
    @property
    def limits(self) -> PtuLimits:
        """Limits read at the last :meth:`connect`.

        :raises DeviceError: never connected.
        """
        if not self._raw:
            raise DeviceError('PTU limits unknown: connect() first')
        pan, tilt = self._resolution('p'), self._resolution('t')
        raw = self._raw
        return PtuLimits(raw['pn'] * pan, raw['px'] * pan, raw['tn'] * tilt, raw['tx'] * tilt,
                         raw['pl'] * pan, raw['pu'] * pan, raw['tl'] * tilt, raw['tu'] * tilt,
                         pan, tilt)

    def _resolution(self, axis: str) -> float:
        return self._raw[f'{axis}r'] * _ARCSEC

    def _read_limits(self, deadline: float) -> bool:
        for name in ('pr', 'tr') + _LIMIT_QUERIES:
            self._raw[name] = self._query_number(name, self._step(deadline))
        raw = self._raw
        return (raw['pr'] > 0 and raw['tr'] > 0 and raw['pn'] < raw['px'] and raw['tn'] < raw['tx']
                and 0 < raw['pl'] <= raw['pu'] and 0 < raw['tl'] <= raw['tu'])

    # -- commands -------------------------------------------------------------------------------
    def set_position(self, pan: float, tilt: float) -> tuple[float, float]:
        """Move to a position, clamped to the limits. In velocity mode the unit ignores it.

        :param pan: rad.
        :param tilt: rad.
        :returns: the angles commanded (clamped and rounded to whole position steps), rad.
        """
        self._ensure()
        counts = (self._count('p', pan, 'pn', 'px'), self._count('t', tilt, 'tn', 'tx'))
        deadline = self._deadline(2)
        self._exchange(Command('pp', counts[0]), deadline)
        self._exchange(Command('tp', counts[1]), deadline)
        self._targets = counts
        return counts[0] * self._resolution('p'), counts[1] * self._resolution('t')

    def set_speed(self, pan: float, tilt: float) -> tuple[float, float]:
        """Set the speeds and return those commanded.

        In position mode the magnitude is used, clamped to the unit's speed bounds; in velocity
        mode the sign gives the direction, 0 stops, other magnitudes are clamped to the bounds.

        :param pan: rad/s.
        :param tilt: rad/s.
        :returns: the speeds commanded, rad/s (whole position steps per second).
        """
        self._ensure()
        counts = (self._speed_count('p', pan), self._speed_count('t', tilt))
        deadline = self._deadline(2)
        self._exchange(Command('ps', counts[0]), deadline)
        self._exchange(Command('ts', counts[1]), deadline)
        return counts[0] * self._resolution('p'), counts[1] * self._resolution('t')

    def set_acceleration(self, pan: float, tilt: float) -> tuple[float, float]:
        """Set the accelerations; returns those set (rad/s², whole position steps).

        :param pan: rad/s²; the magnitude is used, at least one position step/s².
        :param tilt: rad/s², likewise.
        """
        self._ensure()
        counts = tuple(max(1, round(abs(value) / self._resolution(axis)))
                       for axis, value in (('p', pan), ('t', tilt)))
        deadline = self._deadline(2)
        self._exchange(Command('pa', counts[0]), deadline)
        self._exchange(Command('ta', counts[1]), deadline)
        return counts[0] * self._resolution('p'), counts[1] * self._resolution('t')

    def set_velocity_mode(self, enabled: bool) -> None:
        """Pure velocity control (``cv``: signed speeds drive the axes) or independent (``ci``).

        :param enabled: True for ``cv``, False for ``ci``.
        """
        self._ensure()
        self._exchange(Command('cv' if enabled else 'ci'), self._deadline(1))
        self._velocity_mode = enabled

    def halt(self) -> None:
        """Stop both axes now (``h``)."""
        self._ensure()
        self._exchange(Command('h'), self._deadline(1))

    def reset(self) -> None:
        """Recalibrate (``r``); waits up to ``reset_timeout`` for ``!T!T!P!P*``."""
        self._ensure()
        self._exchange(Command('r'), time.monotonic() + self.reset_timeout, ResetDone)
        self._targets = (0, 0)

    def query(self) -> PtuState:
        """Read the angles and desired speeds (four round trips).

        Velocities are the change of the angles over at least 20 ms between queries (the
        reference sample is renewed every 100 ms), so quick successive queries repeat the last
        estimate rather than amplify the one-step quantisation.  The instant the unit read an
        angle is taken as the middle of the query's round trip; the part of a round trip beyond
        the quickest one seen (the line's own time, shared by every read) makes that instant
        uncertain, so the interval must also be :data:`TIMING_MARGIN` times the two samples'
        uncertainty: on a loaded machine, where a round trip is late by tens of milliseconds,
        the estimate waits for a longer baseline instead of dividing by a guessed interval (a
        short interval with a late round trip reads far too fast).
        """
        self._ensure()
        deadline = self._deadline(4)
        asked = time.monotonic()
        pan = self._query_number('pp', deadline)
        replied = time.monotonic()
        now, spread = (asked + replied) / 2.0, (replied - asked) / 2.0   # when the unit read its pan
        self._least_spread = min(self._least_spread, spread)
        late = spread - self._least_spread
        tilt = self._query_number('tp', deadline)
        speeds = [self._query_number(name, deadline) for name in ('ps', 'ts')]
        rp, rt = self._resolution('p'), self._resolution('t')
        if self._last is None:
            self._last, self._velocity = (pan, tilt, now, late), (0.0, 0.0)
        elif (dt := now - self._last[2]) >= max(0.02, TIMING_MARGIN * (late + self._last[3])):
            self._velocity = ((pan - self._last[0]) * rp / dt, (tilt - self._last[1]) * rt / dt)
            if dt >= 0.1:
                self._last = (pan, tilt, now, late)
        elif dt >= 0.1 and late < self._last[3]:
            self._last = (pan, tilt, now, late)          # a surer reference than a late one
        velocities = self._velocity
        if self._velocity_mode:
            moving = any(velocities) or any(speeds)
        else:
            moving = any(velocities) or (round(pan), round(tilt)) != self._targets
        return PtuState(pan * rp, tilt * rt, speeds[0] * rp, speeds[1] * rt,
                        velocities[0], velocities[1], moving, now)

    def command(self, name: str, value: int | None = None, *, timeout: float | None = None
                ) -> Ok:
        """Send any command and return the unit's ``*`` reply: the way to what this class has no
        method for (``le``/``ld``, ``s``/``a``, ``fv``, ``v``).

        :param name: the mnemonic, e.g. ``'pp'`` (1-4 letters).
        :param value: its integer argument, e.g. ``3200``; None for a query or a bare command.
        :param timeout: longest wait for the reply (default ``reply_timeout``).
        :raises DeviceError: the unit answered ``!`` (or DeviceTimeout: it did not answer).
        """
        self._ensure()
        reply = self._exchange(Command(name, value),
                               time.monotonic() + (self.reply_timeout if timeout is None else timeout))
        assert isinstance(reply, Ok)
        return reply

    def poll(self, timeout: float) -> list[PtuEvent]:
        """Asynchronous events (:class:`LimitHit`, an unasked :class:`ResetDone`).

        A limit hit with limits enforced means the unit lost its calibration: call :meth:`reset`.

        :param timeout: the longest wait in seconds when no event is kept already.
        :returns: the events, oldest first; never raises, garbage is counted (:attr:`bad_lines`).
        """
        deadline = time.monotonic() + timeout
        while not self._events:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            self._strays(self._take(self.link.read(remaining)))
        events, self._events = self._events, []
        return events

    # -- helpers --------------------------------------------------------------------------------
    def _ensure(self) -> None:
        if self.link.stats.disconnects != self._disconnects:
            self._stale = True
        if self._stale or not self._connected:
            self.connect(self.connect_timeout)

    def _step(self, deadline: float) -> float:
        """The deadline of one reply within an exchange that must end by ``deadline``."""
        return min(deadline, time.monotonic() + self.reply_timeout)

    def _deadline(self, replies: int) -> float:
        return time.monotonic() + replies * self.reply_timeout

    def _count(self, axis: str, angle: float, low: str, high: str) -> int:
        if not math.isfinite(angle):
            raise DeviceError(f'PTU angle must be finite: {angle}')
        count = round(angle / self._resolution(axis))
        return int(min(max(count, self._raw[low]), self._raw[high]))

    def _speed_count(self, axis: str, speed: float) -> int:
        if not math.isfinite(speed):
            raise DeviceError(f'PTU speed must be finite: {speed}')
        count = round(abs(speed) / self._resolution(axis))
        if self._velocity_mode and count == 0:
            return 0
        count = int(min(max(count, self._raw[f'{axis}l']), self._raw[f'{axis}u']))
        return -count if self._velocity_mode and speed < 0 else count

    def _query_number(self, name: str, deadline: float) -> float:
        reply = self._exchange(Command(name), deadline)
        number = reply.number if isinstance(reply, Ok) else None
        if number is None:
            raise DeviceError(f'{self.link.url}: PTU answered {name!r} without a number: {reply}')
        return number

    def _write(self, data: bytes) -> None:
        if not self.link.write(data):
            self._stale = True
            raise DeviceTimeout(f'{self.link.url}: PTU not there (write failed)')

    def _discard(self, duration: float) -> None:
        deadline = time.monotonic() + duration
        while (remaining := deadline - time.monotonic()) > 0:
            self.link.read(remaining)
        self.link.reset_input()
        self._deframer.reset()

    def _take(self, data: bytes) -> list[Reply]:
        """Feed ``data`` to the deframer; keep events, return the other replies."""
        if not data:
            return []
        skipped = self._deframer.bytes_skipped
        replies = self._deframer.feed(data)
        self.link.stats.bytes_skipped += self._deframer.bytes_skipped - skipped
        self.link.stats.telegrams += len(replies)
        answers: list[Reply] = []
        for reply in replies:
            if isinstance(reply, LimitHit):
                self._events.append(reply)
            else:
                answers.append(reply)
        return answers

    def _exchange(self, command: Command, deadline: float,
                  expect: type[Ok] | type[ResetDone] = Ok) -> Reply:
        """Send ``command`` and wait (until ``deadline``) for its reply."""
        for stray in self._take(self.link.read(0.0)):       # late replies answer nothing now
            self._stray(stray)
        self._write(encode_command(command))
        while (remaining := deadline - time.monotonic()) > 0:
            answers = self._take(self.link.read(remaining))
            for index, reply in enumerate(answers):
                if isinstance(reply, Error):
                    self._strays(answers[index + 1:])
                    raise DeviceError(f'{self.link.url}: PTU refused {command.name!r}'
                                      f'{"" if command.value is None else command.value}: '
                                      f'{reply.message}')
                if isinstance(reply, expect):
                    self._strays(answers[index + 1:])
                    return reply
                self._stray(reply)
        self.link.stats.timeouts += 1
        self._stale = True
        raise DeviceTimeout(f'{self.link.url}: no reply from the PTU to {command.name!r}')

    def _strays(self, replies: list[Reply]) -> None:
        for reply in replies:
            self._stray(reply)

    def _stray(self, reply: Reply) -> None:
        if isinstance(reply, ResetDone):
            self._events.append(reply)
        else:
            self.unsolicited += 1


Ptu46 = PtuDriver  # old name (docs/naming.md)
