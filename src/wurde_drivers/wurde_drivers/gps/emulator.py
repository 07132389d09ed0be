"""An NMEA 0183 GPS receiver on a pseudo-terminal (docs/protocols.md 4).

Every ``1 / rate_hz`` seconds it writes a GGA and a classic RMC sentence (the 11 data fields
without the NMEA 4.1 navigational status, which trips pynmea2, docs/protocols.md 4) for the position
its source gives. The line runs at ``baudrate`` (4800, the NMEA 0183 rate, unless told
otherwise); a driver that opens the port at another speed reads only framing garbage, as it
would from a real receiver.

Faults: :meth:`corrupt_next` (wrong checksums), :meth:`strip_checksum_next`,
:meth:`inject_garbage`, :attr:`silent` (the receiver stops talking) and ``unplugged`` (see
:class:`~wurde_drivers.ports.pty.PtyEmulator`).
"""

from __future__ import annotations

import datetime
import math
import os
import threading
from collections.abc import Callable
from typing import NamedTuple

from ..ports.pty import PtyEmulator
from .codec import GGA, RMC, encode

__all__ = ['GpsEmulator', 'GpsSample', 'fixed_position']


class GpsSample(NamedTuple):
    """What the position source returns: degrees, m above MSL, m/s, degrees true."""

    latitude: float
    longitude: float
    altitude: float = 0.0
    speed: float = 0.0
    course: float = 0.0


#: A position source: called with the seconds since the emulator started.
PositionSource = Callable[[float], 'GpsSample | tuple[float, ...]']


def fixed_position(latitude: float, longitude: float, altitude: float = 0.0) -> PositionSource:
    """A source that stands still at one point.

    :param latitude: degrees.
    :param longitude: degrees.
    :param altitude: metres above MSL.
    """
    sample = GpsSample(latitude, longitude, altitude)
    return lambda elapsed: sample


class GpsEmulator(PtyEmulator):
    """A GPS receiver writing GGA + RMC at ``rate_hz``."""

    def __init__(self, source: PositionSource | None = None, *, rate_hz: float = 1.0,
                 baudrate: int = 4800, satellites: int = 8, quality: int = 1, hdop: float = 0.9,
                 clock: Callable[[], datetime.datetime] | None = None, talker: str = 'GP',
                 tick_s: float = 0.005) -> None:
        """Open the pty; :meth:`start` runs it.

        :param source: position source, called on the emulator thread with the elapsed time (s);
            None: a fixed point.
        :param rate_hz: sentence pairs per second (1 Hz is what most receivers do).
        :param baudrate: the line speed the receiver talks at (4800, 9600 or 38400).
        :param satellites: satellites in use (settable later, as :attr:`satellites`).
        :param quality: GGA fix quality (1 GPS, 2 DGPS, ...; 0 sends no position; settable).
        :param hdop: horizontal dilution of precision (settable).
        :param clock: UTC now; the sentences' time and date come from it.  None: the system clock.
        :param talker: talker id (``GP``; ``GN`` for a multi-constellation receiver).
        :param tick_s: seconds between two turns of the emulator's thread.
        :raises ValueError: another line speed, or a rate that is not positive.
        """
        if baudrate not in (4800, 9600, 38400):
            raise ValueError(f'NMEA receivers talk at 4800, 9600 or 38400 Bd, not {baudrate}')
        if rate_hz <= 0:
            raise ValueError(f'rate_hz must be positive: {rate_hz}')
        super().__init__(tick_s=tick_s)
        self.source = source or fixed_position(48.1173, 11.516666666666667, 545.4)
        self.rate_hz = rate_hz
        self.line_baudrate = baudrate
        self.satellites = satellites
        self.quality = quality
        self.hdop = hdop
        self.clock = clock or (lambda: datetime.datetime.now(datetime.timezone.utc))
        self.talker = talker
        #: Set: the receiver writes nothing (antenna lost, firmware hung).
        self.silent = threading.Event()
        self.sentences_sent = 0
        self._corrupt = 0
        self._strip = 0
        self._started: float | None = None
        self._next = 0.0

    # -- faults ---------------------------------------------------------------------------------
    def corrupt_next(self, count: int = 1) -> None:
        """Give the next ``count`` sentences a wrong checksum.

        :param count: how many; replaces any count still pending.
        """
        self._corrupt = count

    def strip_checksum_next(self, count: int = 1) -> None:
        """Send the next ``count`` sentences without ``*HH``.

        :param count: how many; replaces any count still pending.
        """
        self._strip = count

    def inject_garbage(self, data: bytes | None = None) -> None:
        """Write garbage to the driver now.

        :param data: the bytes; None: 40 random bytes, then a line end.
        """
        self.write(data if data is not None else os.urandom(40) + b'\r\n')

    # -- output ---------------------------------------------------------------------------------
    def sentences(self, elapsed: float) -> list[bytes]:
        """The GGA and RMC lines (also usable without a pty), faults applied.

        :param elapsed: seconds after start, passed to the position source.
        """
        sample = GpsSample(*self.source(elapsed))
        now = self.clock()
        time_of_day = (now.hour * 3600 + now.minute * 60 + now.second
                       + now.microsecond // 10000 / 100.0)
        fix = self.quality > 0
        latitude = sample.latitude if fix else None
        longitude = sample.longitude if fix else None
        course = math.fmod(sample.course, 360.0)
        gga = GGA(time_of_day, latitude, longitude, self.quality, self.satellites,
                  self.hdop if fix else None, sample.altitude if fix else None, 46.9,
                  talker=self.talker)
        rmc = RMC(time_of_day, 'A' if fix else 'V', latitude, longitude, abs(sample.speed),
                  course + 360.0 if course < 0 else course, now.date(), talker=self.talker)
        return [self._fault(encode(gga)), self._fault(encode(rmc))]

    def _fault(self, line: bytes) -> bytes:
        if self._corrupt > 0:
            self._corrupt -= 1
            wrong = (int(line[-4:-2], 16) ^ 0x5A)
            return line[:-4] + f'{wrong:02X}'.encode('ascii') + b'\r\n'
        if self._strip > 0:
            self._strip -= 1
            return line[:-5] + b'\r\n'
        return line

    def tick(self, now: float) -> None:
        """Write the next GGA and RMC when due (garbled while the driver's line speed is wrong).

        :param now: ``time.monotonic()`` of this turn.
        """
        if self._started is None:
            self._started, self._next = now, now
        if now < self._next:
            return
        self._next = max(self._next + 1.0 / self.rate_hz, now - 1.0 / self.rate_hz)
        if self.silent.is_set():
            return
        data = b''.join(self.sentences(now - self._started))
        if self.baudrate not in (0, self.line_baudrate):
            # Wrong speed on the driver's side: what arrives is framing garbage, no line ends.
            data = bytes((byte ^ 0xA5) | 0x80 for byte in data)
        else:
            self.sentences_sent += 2
        self.write(data)
