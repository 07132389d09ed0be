"""sick_server: WURDE's SICKServer (guide 7.5) and Pluto's sickModule (8.1), a SICK LMS/PLS as a module.

It reads its ``<device>`` from ``laser-config.xml``, chosen by the module name (``-n``), drives the
laser through :class:`~wurde_drivers.sick.device.SickDriver` and publishes exactly the streams of
``dummy_sick`` (:class:`~wurde_drivers.streams.laser.LaserStreams`): ``N`` stamped at the scan's
centre, ``N/RWI`` (181 values) stamped at arrival, ``N/Timing``.

Before changing the loop: connecting and resetting the laser block for seconds (a baud search,
Pluto's ~20 s reboot), longer than the 1 s heartbeat TTL, so each runs in a worker thread while
the loop goes on beating, and the loop touches the device only when no worker runs.  A missing
laser is tried again every :data:`RETRY_S` (the module never exits for it); a silent one is
logged once and nothing stale is published; after :data:`RECOVER_AFTER_S` of silence it is
rebooted, and until it streams again every scan period carries −1 ranges (Pluto 8.1).

``log="true"`` appends each scan to ``<data directory>/LaserLog.txt`` (guide 7.5, :func:`log_line`);
the ``invert`` and ``log`` tunables change while the module runs.  docs/wurde-drivers.md
("sick.module") has the detail, the line's parity among it.
"""

from __future__ import annotations

import pathlib
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import TextIO

import serial
from wurde_core import CommsManager, Logger

from ..errors import DriverError
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.retry import RetryGate
from ..streams.laser import LaserStreams
from . import facts
from .config import SickDevice, load_laser_config
from .device import LaserState, Scan, SickDriver

__all__ = ['LOG_NAME', 'SickModule', 'SickRunner', 'log_line', 'main', 'make_laser', 'scan_period']

#: Loop sleep and the longest poll (a scan comes every 13 ms at best, 190 ms at Pluto's defaults).
SLEEP_S = 0.02
#: Seconds between two attempts to connect or reset a laser that is not streaming.
RETRY_S = 1.0
#: Seconds without a scan after which the laser is rebooted (its fatal error ends only so).
RECOVER_AFTER_S = 3.0
#: Longest time the reset request goes round the speeds unanswered, and longest wait for the
#: power-on telegram after it was answered (Pluto 8.1: a reboot takes about 20 s).
RESET_TIMEOUT_S = 30.0
#: Longest the loop waits for a connect or reset worker when the module quits.
QUIT_JOIN_S = 1.0
#: The log file in the data directory (guide 7.5).
LOG_NAME = 'LaserLog.txt'


def scan_period(device: SickDevice) -> float:
    """Seconds between two scans: the mirror's sweeps (0.5° interlaced over 2) or the wire time.

    :param device: the configured device (its values per scan and target speed).
    """
    return facts.scan_period_s(device.values, device.baud)


def silent_after(device: SickDevice) -> float:
    """Seconds without a scan that make a laser silent: four scan periods, at least half a second.

    :param device: the configured device.
    """
    return max(0.5, 4 * scan_period(device))


#: pyserial's parity for the ``parity`` attribute of laser-config.xml.
PARITY = {'none': serial.PARITY_NONE, 'even': serial.PARITY_EVEN}


def make_laser(device: SickDevice) -> SickDriver:
    """The device layer for ``device`` (no I/O), with the configured line parity.

    :param device: a ``<device>`` of laser-config.xml.
    """
    return SickDriver(device.port, kind=device.type, baudrate=device.baud,
                      resolution=device.resolution, units=device.units, invert=device.invert,
                      parity=PARITY[device.parity])


def log_line(stamp: float, ranges: Sequence[float]) -> str:
    """One line of ``LaserLog.txt``: ``[timestamp] : [readings]`` (guide 7.5), newline included.

    Example: ``1700000000.123456 : 1.200 inf 2.345``.

    :param stamp: the scan's centre (the main stream's stamp), seconds since the epoch, written
        with 6 decimals.
    :param ranges: the published ranges, metres in robot order, written with 3 decimals;
        ``inf`` (nothing within range) and ``nan`` (an invalid or dazzled beam) as Python writes them.
    """
    return f'{stamp:.6f} : ' + ' '.join(f'{r:.3f}' for r in ranges) + '\n'


class LaserLog:
    """``LaserLog.txt`` while ``wanted()`` (the ``log`` tunable): opened by ``opener`` when
    logging is switched on, closed when it is switched off; a file that cannot be opened is tried
    again only after the next switch on (its error was logged once)."""

    def __init__(self, wanted: Callable[[], bool], opener: Callable[[], TextIO | None]) -> None:
        """Logging starts closed; the file is opened at the first :meth:`write` while wanted.

        :param wanted: whether logging is on now (the ``log`` tunable).
        :param opener: opens the log for appending, or returns None after logging why it cannot.
        """
        self.wanted = wanted
        self.opener = opener
        self._file: TextIO | None = None
        self._failed = False

    def write(self, stamp: float, ranges: Sequence[float]) -> None:
        """One scan's line, if logging is on; closes the file when it has been switched off.

        :param stamp: the scan's centre, seconds since the epoch.
        :param ranges: the published ranges in metres (only scans: not the −1 of a rebooting laser).
        """
        if not self.wanted():
            self.close()
            self._failed = False
            return
        if self._file is None and not self._failed:
            self._file = self.opener()
            self._failed = self._file is None
        if self._file is not None:
            self._file.write(log_line(stamp, ranges))
            self._file.flush()

    def close(self) -> None:
        """Close the file (idempotent)."""
        file, self._file = self._file, None
        if file is not None:
            file.close()


class SickModule:
    """The module's work per loop turn: connect or reset in a worker, poll, publish, watch."""

    def __init__(self, device: SickDevice, streams: LaserStreams, logger: Logger,
                 log: LaserLog | None = None, invert: Callable[[], bool] | None = None) -> None:
        """Nothing is opened yet: the first :meth:`step` starts the connect.

        :param device: the configured device.
        :param streams: the module's laser streams (registered, info published).
        :param logger: where state changes are logged (once each).
        :param log: ``LaserLog.txt``, or None.
        :param invert: whether the beams are reversed now (the ``invert`` tunable); default the
            device's attribute.
        """
        self.device = device
        self.streams = streams
        self.logger = logger
        self.log = log
        self.invert = invert or (lambda: device.invert)
        self.laser: SickDriver | None = None
        self.streaming = False
        self.silent = False
        self.rebooting = False
        self.fatal_scans = 0
        self._ever_connected = False
        self._failures = 0
        self._retry = RetryGate(RETRY_S)
        self._next_fatal = 0.0
        self._period = scan_period(device)
        self._silent_after = silent_after(device)
        self._worker: threading.Thread | None = None
        self._job = ''
        self._job_error: BaseException | None = None
        self._telegrams_before = 0

    @property
    def where(self) -> str:
        return f'{self.device.type} "{self.device.name}" on {self.device.port}'

    # -- one turn -------------------------------------------------------------------------------
    def step(self, timeout: float) -> int:
        """Connect, reset or poll (up to ``timeout`` s); returns the scans published.

        :param timeout: the longest poll in seconds; a turn that starts or waits for a worker
            returns at once.
        """
        if self._worker is not None:
            if self._worker.is_alive():
                self._while_resetting()
                return 0
            self._finish_job()
        if not self.streaming:
            if self._retry.wait_s(time.monotonic()) == 0.0:     # tried again only after a failure
                self._start_job('recover' if self._ever_connected else 'connect')
            return 0
        assert self.laser is not None
        self.laser.invert = self.invert()
        scans = self.laser.poll(timeout)
        if not scans:
            self._watch_silence()
            return 0
        if self.silent:
            self.silent = False
            self.logger.notice(f'laser {self.where} is back')
        for scan in scans:
            self._publish(scan)
        return len(scans)

    def _publish(self, scan: Scan) -> None:
        self.streams.publish_scan(scan.ranges, centre_stamp=scan.centre_time,
                                  arrival_stamp=scan.arrival_time)
        if self.log is not None:
            self.log.write(scan.centre_time, scan.ranges)

    def _watch_silence(self) -> None:
        assert self.laser is not None
        quiet = self.laser.silent_for()
        if not self.silent and quiet > self._silent_after:
            self.silent = True
            self.logger.warn(f'laser {self.where} is silent (no scan for {quiet:.1f} s); '
                             f'publishing nothing until it is back{self.laser.port_fault}')
        if quiet > RECOVER_AFTER_S:
            self.logger.warn(f'laser {self.where} silent for {quiet:.1f} s: resetting it')
            self.streaming = False
            self._start_job('recover')

    # -- connect and reset in a worker ----------------------------------------------------------
    def _start_job(self, job: str) -> None:
        if self.laser is None or not self._ever_connected:
            self.laser = make_laser(self.device)   # a fresh one until the laser was found
        laser = self.laser
        self._job, self._job_error = job, None
        self._telegrams_before = laser.stats.telegrams
        self.rebooting = False

        def work() -> None:
            try:
                if job == 'connect':
                    laser.connect()
                else:
                    laser.recover(RESET_TIMEOUT_S)
            except DriverError as error:
                self._job_error = error
            except Exception as error:  # a bug: re-raised by the loop, never taken for success
                self._job_error = error

        self._worker = threading.Thread(target=work, name=f'sick-{job}', daemon=True)
        self._worker.start()

    def _while_resetting(self) -> None:
        """While a reset the laser acknowledged is under way, publish −1 ranges every scan period."""
        assert self.laser is not None
        if not self.rebooting:
            if not (self._job == 'recover' and self.laser.state == LaserState.RESETTING
                    and self.laser.stats.telegrams > self._telegrams_before):
                return
            self.rebooting = True
            self._next_fatal = time.monotonic()
            self.logger.warn(f'laser {self.where} is rebooting after a fatal error: publishing -1 '
                             'ranges until it is back')
        now = time.monotonic()
        if now >= self._next_fatal:
            self.streams.publish_fatal(time.time())
            self.fatal_scans += 1
            self._next_fatal = max(self._next_fatal + self._period, now)

    def _finish_job(self) -> None:
        assert self._worker is not None and self.laser is not None
        self._worker.join()
        self._worker = None
        self.rebooting = False
        error = self._job_error
        if error is not None and not isinstance(error, DriverError):
            raise RuntimeError(f'laser {self.where}: {self._job} failed') from error
        if error is not None:
            self.laser.close()    # open afresh next time: the port may be a new device by then
            self._retry.later(time.monotonic())
            if self._failures == 0:
                what = 'not ready' if self._job == 'connect' else 'cannot be reset'
                self.logger.warn(f'laser {self.where} {what}: {error}; trying again every '
                                 f'{RETRY_S:g} s')
            self._failures += 1
            return
        self.streaming = True
        self._failures = 0
        laser = self.laser
        what = 'streaming' if not self._ever_connected else 'reset and streaming again'
        self._ever_connected = True
        self.logger.notice(f'laser {self.where} {what} ({laser.type_string or laser.kind}, '
                           f'{laser.count} values, {laser.units}, {laser.baudrate} baud)')

    def close(self) -> None:
        """Close the port (idempotent).  A worker still blocked in the device after
        :data:`QUIT_JOIN_S` is left to die with the process, which closes the port."""
        if self._worker is not None:
            self._worker.join(QUIT_JOIN_S)
            if self._worker.is_alive():
                return
        if self.laser is not None:
            self.laser.close()


SickRunner = SickModule  # old name (docs/naming.md)


def open_log(manager: CommsManager, logger: Logger) -> TextIO | None:
    """``<data directory>/LaserLog.txt`` for appending, or None (logged) when it cannot be opened.

    :param manager: gives the data directory.
    :param logger: where the file opened, or the reason it was not, is logged.
    """
    path = pathlib.Path(manager.config.get_data_directory()) / LOG_NAME
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle = open(path, 'a', encoding='ascii')  # noqa: SIM115 (closed by main)
    except OSError as error:
        logger.error(f'cannot log the readings to {path}: {error}')
        return None
    logger.notice(f'logging the readings to {path}')
    return handle


def main(argv: list[str] | None = None) -> int:
    """The ``sick_server`` program (also ``sickServer``, ``sickLaser``): one ``<device>`` of
    laser-config.xml as a laser module.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoLaser')
    device = configured_device(manager, argv, 'laser-config.xml', load_laser_config)
    logger = Logger(manager.name)
    streams = LaserStreams(manager.name)
    streams.register(manager)
    manager.register_supplier(logger)
    set_loop(manager, SLEEP_S)
    mount = device.mount
    streams.publish_info(count=device.values, max_range=facts.max_range_m(device.type, device.units),
                         mount_x=mount.x, mount_y=mount.y, mount_z=mount.z, scan_time=scan_period(device))
    invert = manager.tunable('invert', device.invert, 'the laser is mounted upside down: its beams '
                             'are reversed (guide 7.5; CARMEN\'s laser_flipped)')
    logging = manager.tunable('log', device.log, f'append each scan to <data directory>/{LOG_NAME} '
                              '(guide 7.5)')
    log = LaserLog(lambda: bool(logging.value), lambda: open_log(manager, logger))
    runner = SickModule(device, streams, logger, log, lambda: bool(invert.value))

    def close() -> None:
        try:
            runner.close()
        finally:
            log.close()

    return run_loop(manager, lambda: runner.step(SLEEP_S), close)


if __name__ == '__main__':
    sys.exit(main())
