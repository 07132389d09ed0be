"""Device layer of an NMEA 0183 GPS receiver (docs/protocols.md 4; Pluto doc 8.4, the GPS module).

:class:`GpsDriver` reads GGA and RMC sentences from a
:class:`~wurde_drivers.ports.serial_link.SerialLink` (4800 Bd unless the receiver is set otherwise)
and turns each GGA into a :class:`Fix` with x, y in a local metric frame (x east, y north,
:class:`~wurde_drivers.gps.geo.LocalFrame`), as Pluto's gpsmeter proxy does. The frame's origin is
given, or else the first good fix. A fix is *good* when it has more than ``min_satellites - 1``
satellites and a quality at least as accurate as ``min_quality`` (Pluto 8.4: "> 5 satellites and
quality 2 for sub-meter accuracy", the defaults).  Qualities are ranked by accuracy, not by
number (:mod:`~wurde_drivers.gps.quality`): with minimum 2 a good fix is DGPS (2) or RTK (5 float,
4 fixed), never 6 (dead reckoning), 7 (manual) or 8 (simulation).

:meth:`GpsDriver.poll` never raises and never blocks longer than asked: bad checksums,
missing checksums, over-long lines and garbage are counted (:attr:`GpsDriver.counters`,
and ``bad_crc``/``bytes_skipped``/``telegrams`` in the link's stats) and skipped. The link
reopens a vanished port by itself; :meth:`GpsDriver.silent_for` tells how long the receiver
has said nothing useful.
"""

from __future__ import annotations

import dataclasses
import datetime
import math
import time

from ..ports.serial_link import LinkStats, SerialLink
from .codec import GGA, RMC, NmeaDeframer
from .geo import LocalFrame
from .quality import MINIMUMS, meets

__all__ = ['BAUDRATE', 'Fix', 'GpsDriver', 'GpsReceiver']

#: The NMEA 0183 line speed.
BAUDRATE = 4800


@dataclasses.dataclass(frozen=True)
class Fix:
    """One GGA with the frame position and the latest RMC's motion.

    ``latitude``/``longitude`` in degrees (NaN without a position), ``altitude`` in m above MSL
    (NaN if absent), ``hdop`` NaN if absent, ``fix_time`` in s since midnight UTC (NaN if
    absent), ``x``/``y`` in m in the local frame (NaN until there is an origin or without a
    position). ``speed`` (m/s), ``course`` (degrees true) and ``date`` come from the most recent
    RMC, which may be one epoch older than the GGA (receivers send GGA first); None before any.
    ``stamp`` is the monotonic time the sentence's last byte arrived.
    """

    latitude: float
    longitude: float
    altitude: float
    satellites: int
    quality: int
    hdop: float
    fix_time: float
    x: float
    y: float
    good: bool
    speed: float | None
    course: float | None
    date: datetime.date | None
    stamp: float


def _nan(value: float | None) -> float:
    return math.nan if value is None else value


class GpsDriver:
    """An NMEA receiver on a serial link. Construct (no I/O), :meth:`poll` in a loop, :meth:`close`."""

    def __init__(self, link: SerialLink, *, origin: tuple[float, ...] | None = None,
                 min_satellites: int = 6, min_quality: int = 2) -> None:
        """Keep the settings; the link opens on the first read.

        :param link: the receiver's port at its line speed.
        :param origin: (latitude, longitude[, altitude]) of the local frame; None: the first good fix.
        :param min_satellites: satellites a good fix needs (Pluto: more than 5, so 6).
        :param min_quality: GGA quality a good fix needs at least (Pluto: 2, DGPS; ranked by
            accuracy, :func:`~wurde_drivers.gps.quality.meets`).
        :raises ValueError: ``min_quality`` is not a quality a fix can be required to have.
        """
        if min_quality not in MINIMUMS:
            raise ValueError(f'min_quality must be one of {MINIMUMS} (a measured fix quality), '
                             f'not {min_quality}')
        self.link = link
        self.min_satellites = min_satellites
        self.min_quality = min_quality
        self.frame: LocalFrame | None = LocalFrame(*origin) if origin is not None else None
        self._deframer = NmeaDeframer()
        self._rmc: RMC | None = None
        self._last_sentence: float | None = None
        self._started = time.monotonic()
        self.fixes = 0
        self.good_fixes = 0

    @property
    def stats(self) -> LinkStats:
        return self.link.stats

    @property
    def counters(self) -> dict[str, int]:
        """Sentences decoded and each kind of line dropped (see :class:`NmeaDeframer`)."""
        d = self._deframer
        return {'sentences': d.sentences, 'ignored': d.ignored, 'bad_checksum': d.bad_checksum,
                'no_checksum': d.no_checksum, 'too_long': d.too_long, 'malformed': d.malformed,
                'bytes_skipped': d.bytes_skipped, 'fixes': self.fixes,
                'good_fixes': self.good_fixes}

    @property
    def last_rmc(self) -> RMC | None:
        return self._rmc

    def is_good(self, gga: GGA) -> bool:
        """Pluto 8.4's test, with this receiver's thresholds.

        :param gga: a decoded GGA; without a position it is never good.
        """
        return (gga.latitude is not None and gga.longitude is not None
                and gga.satellites >= self.min_satellites
                and meets(gga.quality, self.min_quality))

    def silent_for(self) -> float:
        """Seconds since the last GGA or RMC (since construction if none yet)."""
        last = self._last_sentence if self._last_sentence is not None else self._started
        return time.monotonic() - last

    def poll(self, timeout: float) -> list[Fix]:
        """The fixes that arrive within ``timeout`` s; returns as soon as there is at least one.

        :param timeout: the longest wait in seconds.
        :returns: the fixes, oldest first, each stamped when its sentence arrived; empty at the deadline.
        """
        deadline = time.monotonic() + timeout
        fixes: list[Fix] = []
        while not fixes:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            fixes.extend(self._take(self.link.read(remaining)))
        return fixes

    def close(self) -> None:
        """Close the port (idempotent)."""
        self.link.close()

    def _take(self, data: bytes) -> list[Fix]:
        """The fixes in ``data``, each stamped when its sentence's last byte arrived: the read's
        time less the wire time of the bytes after it.  A read that holds several sentences (a
        module that was late to read, on a loaded machine) gives each its own, older stamp:
        stamping them all with the read's time published two fixes with one stamp."""
        if not data:
            return []
        d = self._deframer
        before = (d.bad_checksum + d.no_checksum, d.bytes_skipped, d.sentences + d.ignored)
        now = time.monotonic()
        sentences: list[tuple[GGA | RMC, float]] = []
        start = 0
        while start < len(data):
            end = data.find(b'\n', start)
            end = len(data) if end < 0 else end + 1
            after = now - (len(data) - end) * 10.0 / max(self.link.baudrate, 1)
            sentences += [(sentence, after) for sentence in d.feed(data[start:end])]
            start = end
        self.link.stats.bad_crc += d.bad_checksum + d.no_checksum - before[0]
        self.link.stats.bytes_skipped += d.bytes_skipped - before[1]
        self.link.stats.telegrams += d.sentences + d.ignored - before[2]
        fixes = []
        for sentence, stamp in sentences:
            self._last_sentence = now
            if isinstance(sentence, RMC):
                self._rmc = sentence
            else:
                fixes.append(self._fix(sentence, stamp))
        return fixes

    def _fix(self, gga: GGA, now: float) -> Fix:
        good = self.is_good(gga)
        if good and self.frame is None:
            assert gga.latitude is not None and gga.longitude is not None
            self.frame = LocalFrame(gga.latitude, gga.longitude,
                                    gga.altitude if gga.altitude is not None else 0.0)
        x = y = math.nan
        if self.frame is not None and gga.latitude is not None and gga.longitude is not None:
            x, y = self.frame.to_xy(gga.latitude, gga.longitude)
        self.fixes += 1
        self.good_fixes += good
        rmc = self._rmc
        return Fix(_nan(gga.latitude), _nan(gga.longitude), _nan(gga.altitude), gga.satellites,
                   gga.quality, _nan(gga.hdop), _nan(gga.time_of_day), x, y, good,
                   rmc.speed if rmc else None, rmc.course if rmc else None,
                   rmc.date if rmc else None, now)


GpsReceiver = GpsDriver  # old name (docs/naming.md)
