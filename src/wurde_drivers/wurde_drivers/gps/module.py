"""gps_module: Pluto's GPS module (Pluto Software Documentation 8.4) for an NMEA receiver.

One GPS stream named after the module (``-n``; the name also picks the ``<device>`` of
``gps-config.xml``, read from ``-c`` or the config directory, :mod:`wurde_drivers.gps.config`),
published through :class:`~wurde_drivers.streams.gps.GpsStreams` exactly as ``dummy_gps`` does:
every GGA the receiver sends is a fix (latitude, longitude, altitude, satellites, quality, HDOP,
UTC time of the fix, and x east, y north in metres — Pluto's gpsmeter grid), stamped with the
time its sentence was read. Consumers judge a fix with the info's thresholds (Pluto: more than
5 satellites and quality 2). The info names the grid's origin: the configured one, else the
first good fix (the info follows as soon as that fix arrives; fixes before it have no x, y).

A receiver that is not there, or says nothing for the configured ``timeout``, is logged once,
and logged again when it talks again; nothing is published meanwhile. The port is reopened about
once a second.
"""

from __future__ import annotations

import sys
import time

from wurde_core import CommsManager, Logger

from ..errors import DeviceError
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.serial_link import SerialLink
from ..streams.gps import GpsStreams
from .config import GpsDevice, load_gps_config
from .device import Fix, GpsDriver

#: Loop sleep and longest wait for sentences per loop (s).
LOOP_S = 0.05
#: Least time between two attempts to open a port that is not there (s).
RETRY_S = 1.0


class GpsModule:
    """The module's work between one :class:`GpsStreams` and one :class:`GpsDriver`."""

    def __init__(self, config: GpsDevice, receiver: GpsDriver, streams: GpsStreams,
                 logger: Logger) -> None:
        """Nothing is opened yet: the first :meth:`step` opens the port.

        :param config: the configured device (port, thresholds, for messages).
        :param receiver: the device layer.
        :param streams: the module's GPS streams, registered.
        :param logger: where the port's and the fixes' changes are logged (once each).
        """
        self.config = config
        self.receiver = receiver
        self.streams = streams
        self.logger = logger
        self.label = f'GPS on {config.port}'
        self.silent = False
        self._info_sent = False
        self._next_open = 0.0
        self._opened_once = False
        self._heard = False

    def _open(self, now: float) -> None:
        """Open the port if it is closed (at most once per :data:`RETRY_S`)."""
        link = self.receiver.link
        if link.is_open or now < self._next_open:
            return
        self._next_open = now + RETRY_S
        try:
            link.open()
        except DeviceError as error:
            if not self.silent:
                self.silent = True
                # The link's error names the port.
                self.logger.warn(f'GPS receiver is not there: {error}; no fixes until it talks '
                                 f'(retrying every {RETRY_S:g} s)')
            return
        if not self._opened_once:
            self._opened_once = True
            self.logger.notice(f'{self.label}: port open at {link.baudrate} Bd')

    def _watch(self) -> None:
        """Log once when the receiver falls silent and once when it talks (again)."""
        quiet = self.receiver.silent_for()
        heard = self.receiver.fixes > 0 or self.receiver.last_rmc is not None
        if not self.silent and quiet > self.config.timeout:
            self.silent = True
            self.logger.warn(f'{self.label} is silent (nothing for {quiet:.1f} s); no fixes '
                             f'until it talks (counters: {self.receiver.counters})'
                             f'{self.receiver.link.fault_note()}')
        elif heard and quiet <= self.config.timeout and (self.silent or not self._heard):
            self.logger.notice(f'{self.label} {"is back" if self._heard else "is talking"}')
            self.silent, self._heard = False, True

    def _publish(self, fix: Fix) -> None:
        wall = time.time() - (time.monotonic() - fix.stamp)
        self.streams.publish_fix(latitude=fix.latitude, longitude=fix.longitude,
                                 altitude=fix.altitude, satellites=fix.satellites,
                                 quality=fix.quality, hdop=fix.hdop, fix_time=fix.fix_time,
                                 x=fix.x, y=fix.y, stamp=wall)

    def _send_info(self) -> None:
        frame = self.receiver.frame
        assert frame is not None
        self.streams.publish_info(latitude=frame.latitude, longitude=frame.longitude,
                                  min_satellites=self.receiver.min_satellites,
                                  min_quality=self.receiver.min_quality)
        self._info_sent = True
        source = 'configured' if self.config.origin is not None else 'first good fix'
        self.logger.notice(f'{self.label}: grid origin ({source}) {frame.latitude:.7f}, '
                           f'{frame.longitude:.7f}')

    def step(self) -> None:
        """One loop's work (called only while the module runs, so what is published is sent):
        wait up to :data:`LOOP_S` for sentences and publish the fixes, the info first."""
        self._open(time.monotonic())
        fixes = self.receiver.poll(LOOP_S) if self.receiver.link.is_open else []
        if not self._info_sent and self.receiver.frame is not None:
            self._send_info()
        for fix in fixes:
            self._publish(fix)
        self._watch()


def main(argv: list[str] | None = None) -> int:
    """The ``gps_module`` program: one ``<device>`` of gps-config.xml as a GPS stream.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status.
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoGPS')
    config = configured_device(manager, argv, 'gps-config.xml', load_gps_config)
    receiver = GpsDriver(SerialLink(config.port, config.baud, retry_s=RETRY_S),
                         origin=config.origin, min_satellites=config.min_satellites,
                         min_quality=config.min_quality)
    streams = GpsStreams(manager.name, mount=config.mount)
    logger = Logger(manager.name)
    streams.register(manager)
    manager.register_supplier(logger)
    set_loop(manager, LOOP_S)
    module = GpsModule(config, receiver, streams, logger)
    return run_loop(manager, module.step, receiver.close)


if __name__ == '__main__':
    sys.exit(main())
