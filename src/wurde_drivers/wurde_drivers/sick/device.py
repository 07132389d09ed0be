"""The SICK LMS 2xx / PLS driver over a :class:`~wurde_drivers.ports.serial_link.SerialLink` (no ROS).

Life cycle (docs/style.md 5): construct (no I/O) → :meth:`SickDriver.connect` (may raise) →
:meth:`SickDriver.poll` (never blocks longer than asked, never raises on bad bytes) → :meth:`close`
(idempotent).  One thread uses an instance.

``connect`` replays a CARMEN-like start-up (docs/protocols.md 1.7): a search for the device's
current speed, installation mode, the switch to the target speed, the LMS's variant and units,
continuous mode; the defaults follow Pluto 8.1 (cm, 361 values, 38400 baud).  A speed the port
refuses is never taken for done
(:meth:`~wurde_drivers.ports.serial_link.SerialLink.set_baudrate` raises).

A :class:`Scan` carries ``arrival_time`` (just after the read that brought its last byte) and
``centre_time``, when the mirror was in the middle of the scan: the telegram's wire time and half
a mirror sweep earlier (as :func:`.facts.centre_offset_s`; Pluto 8.1's "about 200 ms earlier").

Fatal errors (Pluto 8.1: the server must reboot the laser, about 20 s, all data -1 meanwhile):
the driver notices only silence (:meth:`silent_for`); :meth:`recover` resets the device and
connects again, :attr:`state` saying ``RESETTING`` meanwhile (so the module can publish -1
ranges) and ``FAILED`` if it did not work.  docs/wurde-drivers.md ("sick.device") gives the
sequences step by step.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import time

import serial

from ..errors import CodecError, DeviceError, DeviceTimeout
from ..ports.serial_link import LinkStats, SerialLink
from . import codec as sick
from . import facts

#: Speeds tried when looking for the device, in CARMEN's order (docs/protocols.md 1.7).
SEARCH_BAUDS = (9600, 19200, 38400, 500000)


class LaserState(enum.Enum):
    CLOSED = 'closed'
    CONNECTING = 'connecting'
    STREAMING = 'streaming'
    RESETTING = 'resetting'
    FAILED = 'failed'


@dataclasses.dataclass(frozen=True)
class Scan:
    """One scan: ``ranges`` in metres in beam order (reversed when the laser is inverted).

    ``math.inf`` marks "value > maximum" (8183) and ranges beyond :func:`.facts.max_range_m`; ``math.nan``
    marks the other error codes (invalid, dazzling, ...).  ``raw`` are the 13-bit values as sent, in
    the same order as ``ranges``.  Beam 0 is at ``angle_min`` (right-hand end when upright).
    """

    ranges: tuple[float, ...]
    raw: tuple[int, ...]
    units: str
    count: int
    arrival_time: float
    centre_time: float
    fov_deg: float = 180.0

    @property
    def angle_min(self) -> float:
        return -math.radians(self.fov_deg) / 2.0

    @property
    def angle_increment(self) -> float:
        return math.radians(self.fov_deg) / max(self.count - 1, 1)


class SickDriver:
    """A SICK LMS 2xx or PLS on a serial port; construction does no I/O (see :meth:`connect`)."""

    def __init__(self, port: str, *, kind: str = 'LMS', baudrate: int = 38400,
                 resolution: float = 0.5, units: str = 'cm', invert: bool = False,
                 reply_timeout: float = 0.3, parity: str | None = None) -> None:
        """Check the settings and prepare the link, closed, at the power-up speed of 9600 baud.

        :param port: a pyserial URL or device path.
        :param kind: ``'LMS'`` or ``'PLS'`` (a PLS line is 8E1, docs/protocols.md 1.1).
        :param baudrate: target speed, one of 9600, 19200, 38400, 500000.
        :param resolution: degrees between beams over 180°: 1.0 (181 values) or 0.5 (361).
        :param units: ``'cm'`` (81.82 m max) or ``'mm'`` (8.182 m max); a PLS supports cm only.
        :param invert: reverse the beam order (laser mounted upside down, WURDE guide 7.5).
        :param reply_timeout: seconds to wait for the reply to a request (plus, while a frame is
            half received, the time the longest telegram takes on the wire at the current speed).
        :param parity: ``serial.PARITY_NONE`` or ``serial.PARITY_EVEN``; None: even for a PLS,
            none for an LMS (the devices speak 8E1 / 8N1).  A pty cannot do parity (docs/protocols.md 6),
            so a PLS emulator is driven with ``serial.PARITY_NONE`` (``parity="none"`` in laser-config.xml).
        :raises ValueError: an unknown kind or speed, or a resolution and units the kind cannot run.
        """
        if kind not in sick.PASSWORDS:
            raise ValueError(f'kind must be LMS or PLS, not {kind!r}')
        if baudrate not in sick.BAUD_CODES:
            raise ValueError(f'baudrate must be one of {sorted(sick.BAUD_CODES)}')
        if resolution not in facts.VALUES_AT:
            raise ValueError('resolution must be 1.0 or 0.5')
        problem = facts.variant_error(kind, facts.VALUES_AT[resolution], units)
        if problem is not None:
            raise ValueError(problem)
        self.kind = kind
        self.target_baud = baudrate
        self.resolution = resolution
        self.units = units
        self.invert = invert
        self.reply_timeout = reply_timeout
        if parity is None:
            parity = serial.PARITY_EVEN if kind == 'PLS' else serial.PARITY_NONE
        self._link = SerialLink(port, 9600, parity=parity)
        self._deframer = sick.Deframer(sick.DEVICE_ADDRESS)
        self._counted = (0, 0, 0)
        self._backlog: list[tuple[sick.Telegram, float]] = []
        self._known_baud: int | None = None
        self._last_scan = time.monotonic()
        self.state = LaserState.CLOSED
        self.type_string = ''
        #: B0 telegrams with a good CRC whose content did not parse.
        self.bad_scans = 0
        self.scans = 0

    # -- properties -----------------------------------------------------------------------------
    @property
    def count(self) -> int:
        """Values per scan: 181 or 361."""
        return facts.VALUES_AT[self.resolution]

    @property
    def max_range(self) -> float:
        return facts.max_range_m(self.kind, self.units)

    @property
    def baudrate(self) -> int:
        """The speed the line is at now."""
        return self._link.baudrate

    @property
    def parity(self) -> str:
        """The line's parity, ``serial.PARITY_NONE`` or ``serial.PARITY_EVEN``."""
        return self._link.parity

    @property
    def stats(self) -> LinkStats:
        return self._link.stats

    @property
    def port_fault(self) -> str:
        """The port's last fault for a log line (``''`` if none), see
        :meth:`~wurde_drivers.ports.serial_link.SerialLink.fault_note`."""
        return self._link.fault_note()

    def silent_for(self) -> float:
        """Seconds since the last good scan (or since :meth:`connect` started)."""
        return time.monotonic() - self._last_scan

    # -- bytes in -------------------------------------------------------------------------------
    def _feed(self, data: bytes) -> list[sick.Telegram]:
        telegrams = self._deframer.feed(data)
        d = self._deframer
        now = (d.telegrams, d.bad_crc, d.bytes_skipped)
        stats = self._link.stats
        stats.telegrams += now[0] - self._counted[0]
        stats.bad_crc += now[1] - self._counted[1]
        stats.bytes_skipped += now[2] - self._counted[2]
        self._counted = now
        return telegrams

    def _forget_input(self) -> None:
        """Drop half-received frames and unread telegrams (after a change of line speed)."""
        self._deframer.reset()
        self._backlog.clear()

    def _wire_time(self, nbytes: int) -> float:
        return nbytes * 10.0 / self._link.baudrate

    def _await(self, commands: set[int], timeout: float) -> sick.Telegram | None:
        """Read until a telegram whose command is in ``commands`` (any if empty) arrives.

        Gives up after ``timeout`` s, or, while a frame is half received, after the time the
        longest telegram takes on the wire on top of that (a slow line is not a silent one), or
        at a NAK byte when waiting for a particular reply.  Telegrams read after the one returned
        stay in the backlog (with their arrival time) for the next call or :meth:`poll`.
        """
        start = time.monotonic()
        grace = self._wire_time(sick.telegram_size(401))
        naks = self._deframer.naks
        while True:
            while self._backlog:
                telegram, _ = self._backlog.pop(0)
                if telegram.command in commands or not commands:
                    return telegram
            if commands and self._deframer.naks != naks:
                return None                             # the request was refused: try again
            extra = grace if self._deframer.pending else 0.0
            remaining = start + timeout + extra - time.monotonic()
            if remaining <= 0:
                return None
            data = self._link.read(remaining)
            if data:
                arrival = time.time()
                self._backlog += [(telegram, arrival) for telegram in self._feed(data)]
            elif not self._link.is_open:
                time.sleep(min(remaining, 0.05))

    def _transact(self, frame: bytes, reply: int, *, attempts: int = 2) -> sick.Telegram:
        """Send ``frame`` and return the reply telegram ``reply`` (other telegrams are skipped).

        :raises DeviceError: the device answered 0x92 (not acknowledged).
        :raises DeviceTimeout: no reply after ``attempts`` tries (each NAK or silence is a try).
        """
        for _ in range(attempts):
            self._backlog.clear()       # scans of a stream being stopped; no reply comes unasked
            if not self._link.write(frame):
                raise DeviceError(f'{self._link.url}: cannot write')
            telegram = self._await({reply, sick.REPLY_NOT_ACK}, self.reply_timeout)
            if telegram is None:
                self._link.stats.timeouts += 1
                continue
            if telegram.command == sick.REPLY_NOT_ACK:
                raise DeviceError(f'request 0x{frame[4]:02x} not acknowledged (0x92)')
            return telegram
        raise DeviceTimeout(f'{self._link.url}: no reply 0x{reply:02x} to request 0x{frame[4]:02x} '
                            f'at {self._link.baudrate} baud')

    def _mode(self, frame: bytes, what: str) -> None:
        telegram = self._transact(frame, sick.REPLY_MODE)
        try:
            ok = sick.decode_mode_reply(telegram.data)
        except CodecError as error:
            raise DeviceError(f'{what}: {error}') from error
        if not ok:
            raise DeviceError(f'{what}: refused by the device')

    # -- life cycle -----------------------------------------------------------------------------
    def _bauds(self) -> list[int]:
        """:data:`SEARCH_BAUDS`, the speed the device was last known to run at first."""
        return list(dict.fromkeys(([self._known_baud] if self._known_baud else [])
                                  + list(SEARCH_BAUDS)))

    def _listen_at(self, baud: int) -> bool:
        """Put the line at ``baud`` with nothing read pending; False if the port refused that
        speed (the device cannot be heard at it, so it is skipped).

        :raises DeviceError: the port failed while changing speed (it is closed).
        """
        try:
            self._link.set_baudrate(baud)
        except DeviceError:
            if not self._link.is_open:
                raise
            return False
        self._link.reset_input()
        self._forget_input()
        return True

    def _find_baud(self) -> int:
        for baud in self._bauds():
            if not self._listen_at(baud):
                continue
            for frame, reply in ((sick.stop_continuous_request(), sick.REPLY_MODE),
                                 (sick.status_request(), sick.REPLY_STATUS)):
                if not self._link.write(frame):
                    raise DeviceError(f'{self._link.url}: cannot write')
                first = self._await(set(), self.reply_timeout)
                if first is not None:
                    if first.command != reply:
                        # A scan of the running stream came first: take the probe's own answer
                        # too, so that it is not taken later for the answer to another request.
                        self._await({reply}, self.reply_timeout)
                    self._known_baud = baud
                    return baud
        self._link.stats.timeouts += 1
        raise DeviceTimeout(f'{self._link.url}: no SICK {self.kind} answers at any of '
                            f'{", ".join(map(str, SEARCH_BAUDS))} baud')

    def connect(self) -> None:
        """Find the device, configure it and start continuous mode.

        :raises DeviceError: the port cannot be opened or the device refuses a setting.
        :raises DeviceTimeout: the device does not answer.
        """
        self.state = LaserState.CONNECTING
        self._last_scan = time.monotonic()
        try:
            self._link.open()
            baud = self._find_baud()
            self._mode(sick.stop_continuous_request(), 'stop continuous mode')
            self._mode(sick.install_mode_request(self.kind), 'installation mode')
            if baud != self.target_baud:
                self._mode(sick.baud_request(self.target_baud), f'{self.target_baud} baud')
                self._link.set_baudrate(self.target_baud)
                self._forget_input()
            self._known_baud = self.target_baud
            if self.kind == 'LMS':
                self._configure_lms()
            else:
                self._transact(sick.status_request(), sick.REPLY_STATUS)  # proves the new speed
            self._mode(sick.start_continuous_request(), 'continuous mode')
        except DeviceError:
            self.state = LaserState.FAILED
            raise
        self._last_scan = time.monotonic()
        self.state = LaserState.STREAMING

    def _configure_lms(self) -> None:
        try:
            self.type_string = sick.decode_ba(self._transact(sick.type_request(),
                                                             sick.REPLY_TYPE).data)
            step = 100 if self.resolution == 1.0 else 50
            variant = sick.decode_bb(self._transact(sick.variant_request(180, step),
                                                    sick.REPLY_VARIANT).data)
            if not variant.ok or (variant.angle, variant.resolution) != (180, step):
                raise DeviceError(f'variant 180°/{self.resolution}° refused')
            config = sick.decode_f4(self._transact(sick.read_config_request(),
                                                   sick.REPLY_READ_CONFIG).data)
            if config.units != self.units:
                ok, config = sick.decode_f7(self._transact(
                    sick.write_config_request(config.with_units(self.units)),
                    sick.REPLY_WRITE_CONFIG).data)
                if not ok or config.units != self.units:
                    raise DeviceError(f'units {self.units} refused')
        except CodecError as error:
            raise DeviceError(f'malformed reply: {error}') from error

    def recover(self, reset_timeout: float = 30.0) -> None:
        """Reset the device (``10`` → ``91``, then ``90`` at 9600 baud) and :meth:`connect` again.

        The reset goes out at the speed the device was last known to run at, then at each of the
        other :data:`SEARCH_BAUDS`, round after round, until the device acknowledges it (``91``)
        or ``reset_timeout`` has passed (one round at least): a device in a fatal error hears
        nothing else and only at its own speed, and may miss one reset.  When no speed got an
        acknowledgement (the device is merely silent, or unplugged) or the device refused the reset
        (``92``: it is alive), it goes straight to :meth:`connect`.  Blocks up to twice
        ``reset_timeout`` (plus one ``reply_timeout``) plus a connect.

        :param reset_timeout: seconds to go round the speeds for an acknowledgement, and again to
            wait for the ``90`` power-on telegram after it.
        :raises DeviceError: (or DeviceTimeout) when the device cannot be brought back;
            :attr:`state` is then ``FAILED``.
        """
        self.state = LaserState.RESETTING
        try:
            self._link.open()
        except DeviceError:
            self.state = LaserState.FAILED
            raise
        try:
            if self._reset(reset_timeout):
                self._link.set_baudrate(9600)
                self._forget_input()
                self._known_baud = 9600
                self._await({sick.REPLY_POWER_ON}, reset_timeout)
        except DeviceError:
            self.state = LaserState.FAILED
            raise
        self.connect()

    def _reset(self, timeout: float) -> bool:
        """Send the reset at each speed in turn (see :meth:`recover`); True once acknowledged."""
        deadline = time.monotonic() + timeout
        bauds, tried = self._bauds(), 0
        while bauds and (tried < len(bauds) or time.monotonic() < deadline):
            baud = bauds[tried % len(bauds)]
            if not self._listen_at(baud):
                bauds.remove(baud)                  # the port cannot run at it: never again
                continue
            tried += 1
            if not self._link.write(sick.reset_request()):
                return False            # the line cannot be written: connect reports it
            reply = self._await({sick.REPLY_RESET, sick.REPLY_NOT_ACK}, self.reply_timeout)
            if reply is None:
                self._link.stats.timeouts += 1      # not heard at this speed: the next one
            elif reply.command == sick.REPLY_NOT_ACK:
                self._known_baud = baud             # refused, so alive at this speed
                return False
            else:
                return True
        return False

    def poll(self, timeout: float) -> list[Scan]:
        """Scans that arrive within ``timeout`` s; returns as soon as there is at least one.

        :param timeout: the longest wait in seconds (negative counts as 0).
        :returns: the scans decoded, oldest first; empty when none came (bad bytes are counted in
            :attr:`stats`, never raised).
        """
        deadline = time.monotonic() + max(timeout, 0.0)
        scans: list[Scan] = []
        received, self._backlog = self._backlog, []
        while True:
            for telegram, arrival in received:
                if telegram.command == sick.REPLY_SCAN:
                    scan = self._scan(telegram, arrival)
                    if scan is not None:
                        scans.append(scan)
            remaining = deadline - time.monotonic()
            if scans or remaining <= 0:
                return scans
            data = self._link.read(remaining)
            if data:
                arrival = time.time()
                received = [(telegram, arrival) for telegram in self._feed(data)]
            else:
                received = []
                if not self._link.is_open:
                    time.sleep(min(remaining, 0.05))

    def _scan(self, telegram: sick.Telegram, arrival: float) -> Scan | None:
        try:
            decoded = sick.decode_b0(telegram.data)
        except CodecError:
            self.bad_scans += 1
            return None
        scale, limit = sick.UNIT_SCALE[decoded.units], self.max_range
        ranges = []
        for value in decoded.values:
            if value in sick.ERROR_CODES:
                ranges.append(math.inf if value == sick.VALUE_TOO_FAR else math.nan)
            else:
                metres = value * scale
                ranges.append(math.inf if metres > limit else metres)
        raw = decoded.values
        if self.invert:
            ranges.reverse()
            raw = raw[::-1]
        size = 6 + 1 + len(telegram.data) + 1
        centre = arrival - self._wire_time(size) - 0.5 / facts.MIRROR_HZ
        self._last_scan = time.monotonic()
        self.scans += 1
        return Scan(tuple(ranges), raw, decoded.units, decoded.count, arrival, centre)

    def close(self) -> None:
        """Close the port (idempotent).  The device is left as it is (streaming or not)."""
        self._link.close()
        self.state = LaserState.CLOSED

    def __enter__(self) -> SickDriver:
        self.connect()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


SickLaser = SickDriver  # old name (docs/naming.md)
