"""An emulated SICK LMS 2xx or PLS on a pseudo-terminal, with the real telegrams (docs/protocols.md 1).

It behaves as the device does wherever a driver can tell: it powers up at 9600 baud with values
on request, 180° at 1° (PLS: 0.5°), in cm; it answers the requests a driver sends at start-up
(install mode, variant, config, type, status, one scan, baud switch), ACK byte first, and a
request with a bad CRC with a lone NAK; in continuous mode it sends B0 telegrams paced by the
mirror and by the line.  A request sent at a line speed other than the device's is ignored, so a
driver's baud search means on a pty what it means on a line.  docs/wurde-drivers.md
("sick.emulator") lists each behaviour and the pacing.

Ranges come from ``scan_source(count, fov_deg) -> metres``, beam 0 at the right-hand end, as the
device sends it; an upside-down mounting is the driver's business, not the emulator's.

Parity cannot be emulated on a pty (docs/protocols.md 6), so a driver talks to an emulated PLS
without parity (``parity="none"`` in laser-config.xml); on a real line it uses even parity.

Faults for tests, callable from any thread: :meth:`corrupt_next`, :meth:`inject_garbage`,
:attr:`silent`, :meth:`fatal_error`, :meth:`miss_resets`, :meth:`power_cycle`, and ``unplugged``
from :class:`PtyEmulator`.  After :meth:`fatal_error` the device answers only the reset request
``10``, then reboots (``91``, then ``90`` at 9600 baud after ``reset_s``): our choice, which the
driver's :meth:`~wurde_drivers.sick.device.SickDriver.recover` follows (docs/protocols.md,
"Additions").  Pluto 8.1 says a real reset takes about 20 s.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Sequence

from ..ports.pty import PtyEmulator
from . import codec as sick
from . import facts

ScanSource = Callable[[int, float], Sequence[float]]

#: Angles and resolutions (1/100°) the variant request accepts; 0.25° only at 100° (1.6).
_VARIANTS = {(180, 100), (180, 50), (100, 100), (100, 50), (100, 25)}
_TYPES = {'LMS': 'LMS200;30106', 'PLS': 'PLS101-312'}


def constant_source(metres: float = 4.0) -> ScanSource:
    """A scan source that sees a circle of ``metres`` around the scanner.

    :param metres: the range of every beam.
    """
    def source(count: int, fov_deg: float) -> Sequence[float]:
        return [metres] * count
    return source


class SickEmulator(PtyEmulator):
    """An LMS 2xx (``kind='LMS'``) or PLS (``kind='PLS'``) on a pty; ``path`` is its port."""

    def __init__(self, *, kind: str = 'LMS', scan_source: ScanSource | None = None,
                 reset_s: float = 0.3, status_byte: int = 0x10, tick_s: float = 0.002) -> None:
        """Open the pty and power up (9600 baud, values on request); :meth:`start` runs it.

        :param kind: ``'LMS'`` or ``'PLS'``.
        :param scan_source: ``(count, fov_deg) -> ranges in metres``, beam 0 at the right-hand end;
            None: 4 m everywhere.
        :param reset_s: seconds a reset takes before the power-on telegram.
        :param status_byte: the STATUS byte of every reply (real captures show 0x10).
        :param tick_s: seconds between two turns of the emulator's thread (the pacing's granularity).
        :raises ValueError: an unknown kind.
        """
        if kind not in sick.PASSWORDS:
            raise ValueError(f'kind must be LMS or PLS, not {kind!r}')
        super().__init__(tick_s=tick_s)
        self.kind = kind
        self.scan_source = scan_source or constant_source()
        self.reset_s = reset_s
        self.status_byte = status_byte
        #: Set: the device sends nothing and ignores whatever it is sent.
        self.silent = threading.Event()
        self._faults = threading.Lock()
        self._corrupt = 0
        self._garbage = b''
        self._garbage_frames = 0
        self._fatal = False
        self._resets_to_miss = 0
        #: Reset requests not heard because of :meth:`miss_resets`.
        self.resets_missed = 0
        self._deframer = sick.Deframer(sick.HOST_ADDRESS)
        self.scans_sent = 0
        self.bytes_garbled = 0          # request bytes ignored because the speeds differed
        self.commands: list[int] = []   # every request command understood, in order
        self._power_up()

    # -- state ----------------------------------------------------------------------------------
    def _power_up(self) -> None:
        self.device_baud = 9600
        self.mode = sick.MODE_ON_REQUEST
        self.angle, self.resolution = (180, 50) if self.kind == 'PLS' else (180, 100)
        self.config = sick.SickConfig()
        self._reset_at: float | None = None
        self._next_scan = 0.0
        self._deframer.reset()

    @property
    def count(self) -> int:
        """Values per scan in the current variant."""
        return sick.value_count(self.angle, self.resolution)

    @property
    def scan_period(self) -> float:
        """Seconds between two B0 telegrams in continuous mode at the device's baud rate."""
        mirror = sick.interlace(self.resolution) / facts.MIRROR_HZ
        wire = sick.telegram_size(self.count) * 10.0 / self.device_baud
        return max(mirror, wire)

    # -- fault injection ------------------------------------------------------------------------
    def corrupt_next(self, telegrams: int = 1) -> None:
        """Send the next ``telegrams`` telegrams with a wrong CRC.

        :param telegrams: how many; added to any still pending.
        """
        with self._faults:
            self._corrupt += telegrams

    def inject_garbage(self, data: bytes = b'\x55\xaa\x02\x00\xff', frames: int = 1) -> None:
        """Write ``data`` before each of the next ``frames`` telegrams.

        :param data: the garbage bytes (the default holds a false STX).
        :param frames: how many telegrams it precedes; replaces any garbage still pending.
        """
        with self._faults:
            self._garbage, self._garbage_frames = bytes(data), frames

    def fatal_error(self) -> None:
        """Stop streaming and answering until a reset request ``10`` (see the module docstring)."""
        with self._faults:
            self._fatal = True

    def miss_resets(self, count: int = 1) -> None:
        """Do not hear the next ``count`` reset requests (a fatal error stays as it is).

        :param count: how many; added to any still pending.
        """
        with self._faults:
            self._resets_to_miss += count

    def power_cycle(self) -> None:
        """Switch off and on: the device says ``90`` and is at 9600 baud with its defaults."""
        with self._faults:
            self._fatal = False
        self._reset_at = self._now()        # the emulator's thread powers up at its next tick

    @property
    def fatal(self) -> bool:
        return self._fatal

    # -- output ---------------------------------------------------------------------------------
    def _send(self, frame: bytes, *, ack: bool = True) -> None:
        if self.silent.is_set():
            return
        with self._faults:
            prefix = b''
            if self._garbage_frames > 0:
                self._garbage_frames -= 1
                prefix = self._garbage
            if self._corrupt > 0:
                self._corrupt -= 1
                frame = frame[:-2] + bytes((frame[-2] ^ 0xFF, frame[-1]))
        wire = prefix + (bytes((sick.ACK,)) if ack else b'') + frame
        if self.baudrate != self.device_baud:
            # At the wrong speed the driver sees noise; never an STX, so never a false frame.
            wire = bytes((b * 7 + 0x33) & 0xFF for b in wire).replace(b'\x02', b'\xfd')
        self.write(wire)

    def _reply(self, command: int, data: bytes = b'', *, ack: bool = True) -> None:
        self._send(sick.reply(command, data, self.status_byte), ack=ack)

    def _scan_data(self) -> bytes:
        units = self.config.units
        scale = sick.UNIT_SCALE[units]
        # An LMS's limit is its encoding (past 8182 units is 8183); a PLS's is its 50 m.
        limit = facts.max_range_m('PLS', 'cm') if self.kind == 'PLS' else math.inf
        values = []
        for metres in self.scan_source(self.count, float(self.angle)):
            if math.isnan(metres) or metres < 0:
                values.append(8191)
            elif metres > limit or math.isinf(metres):
                values.append(sick.VALUE_TOO_FAR)
            else:
                values.append(min(round(metres / scale), sick.VALUE_TOO_FAR))
        return sick.encode_b0(values, units)

    # -- input ----------------------------------------------------------------------------------
    def on_bytes(self, data: bytes) -> None:
        """Take request bytes from the driver: ignored while silent or at the wrong speed, NAK on a bad CRC.

        :param data: the bytes read from the pty, in any pieces.
        """
        if self.silent.is_set():
            return
        if self.baudrate != self.device_baud:
            self.bytes_garbled += len(data)
            return
        naks = self._deframer.bad_crc
        telegrams = self._deframer.feed(data)
        if self._deframer.bad_crc != naks and not self._fatal:
            self._send(bytes((sick.NAK,)), ack=False)
        for telegram in telegrams:
            self._handle(telegram)

    def _handle(self, telegram: sick.Telegram) -> None:
        command, data = telegram.command, telegram.data
        if self._fatal and command != sick.CMD_RESET:
            return
        if command == sick.CMD_RESET and self._resets_to_miss > 0:
            with self._faults:
                self._resets_to_miss -= 1
            self.resets_missed += 1
            return
        self.commands.append(command)
        if command == sick.CMD_RESET:
            self._reply(sick.REPLY_RESET)
            with self._faults:
                self._fatal = False
            self.mode = sick.MODE_ON_REQUEST
            self._reset_at = self._now() + self.reset_s
        elif command == sick.CMD_MODE and data:
            self._change_mode(data)
        elif command == sick.CMD_SCAN and data[:1] == b'\x01':
            self.scans_sent += 1
            self._reply(sick.REPLY_SCAN, self._scan_data())
        elif command == sick.CMD_STATUS:
            status = sick.SickStatus(operating_mode=self.mode, error=0, scan_angle=self.angle,
                                     resolution=self.resolution, units_code=self.config.units_code,
                                     measuring_mode=self.config.measuring_mode)
            self._reply(sick.REPLY_STATUS, status.encode())
        elif command == sick.CMD_TYPE:
            self._reply(sick.REPLY_TYPE, _TYPES[self.kind].encode('ascii'))
        elif command == sick.CMD_VARIANT and len(data) >= 4:
            angle, resolution = data[0] | data[1] << 8, data[2] | data[3] << 8
            ok = (angle, resolution) in _VARIANTS and (self.kind == 'LMS' or resolution == 50)
            if ok:
                self.angle, self.resolution = angle, resolution
            self._reply(sick.REPLY_VARIANT,
                        sick.VariantReply(ok, self.angle, self.resolution).encode())
        elif command == sick.CMD_READ_CONFIG:
            self._reply(sick.REPLY_READ_CONFIG, self.config.encode())
        elif command == sick.CMD_WRITE_CONFIG:
            ok = self.mode == sick.MODE_INSTALL and 7 <= len(data) <= sick.CONFIG_SIZE
            if ok:
                self.config = self.config.patched(data)
            self._reply(sick.REPLY_WRITE_CONFIG, bytes((1 if ok else 0,)) + self.config.encode())
        else:
            self._reply(sick.REPLY_NOT_ACK)

    def _change_mode(self, data: bytes) -> None:
        code = data[0]
        if code == sick.MODE_INSTALL:
            ok = bytes(data[1:9]) == sick.PASSWORDS[self.kind]
            if ok:
                self.mode = code
            self._reply(sick.REPLY_MODE, b'\x00' if ok else b'\x01')
        elif code in (sick.MODE_CONTINUOUS, sick.MODE_ON_REQUEST):
            self.mode = code
            self._reply(sick.REPLY_MODE, b'\x00')
            self._next_scan = self._now() + self.scan_period
        elif code in sick.BAUD_BY_CODE:
            self._reply(sick.REPLY_MODE, b'\x00')     # at the old rate, then switch (1.5)
            self.device_baud = sick.BAUD_BY_CODE[code]
        else:
            self._reply(sick.REPLY_MODE, b'\x01')

    @staticmethod
    def _now() -> float:
        return time.monotonic()

    # -- streaming ------------------------------------------------------------------------------
    def tick(self, now: float) -> None:
        """Finish a reset that is due, or send the next B0 telegram in continuous mode when its time has come.

        :param now: ``time.monotonic()`` of this turn.
        """
        if self._reset_at is not None and now >= self._reset_at:
            self._power_up()
            self._reply(sick.REPLY_POWER_ON, _TYPES[self.kind].encode('ascii'), ack=False)
            return
        if self._fatal or self.mode != sick.MODE_CONTINUOUS or now < self._next_scan:
            return
        period = self.scan_period
        self._next_scan += period
        if self._next_scan < now:
            # After a pause (unplugged, a slow tick) start again from now: no burst.
            self._next_scan = now + period
        if self.silent.is_set():
            return
        self.scans_sent += 1
        self._reply(sick.REPLY_SCAN, self._scan_data(), ack=False)
