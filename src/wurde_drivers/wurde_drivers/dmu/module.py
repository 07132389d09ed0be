"""dmu_module: Pluto's dmuModule (Pluto Software Documentation 8.2), the Crossbow DMU as a module.

It reads its ``<device>`` (chosen by the module name, ``-n``, default PlutoDMU) from
``dmu-config.xml`` (:mod:`wurde_drivers.dmu.config`; ``-c`` or the config directory), drives the
unit through :class:`~wurde_drivers.dmu.device.DmuDriver` and publishes exactly the streams of
the dummy DMU (:class:`~wurde_drivers.streams.dmu.DmuStreams`): ``N/Raw`` for every sample,
stamped when it was sent (a burst read together is spread back by the unit's time word), and
``N``, low-pass filtered with the heading integrated and the stamp moved back by the filter
delay.

Life cycle: a unit that is not there at start is tried again about once a second from inside the
loop (the module never exits for a missing device, which would make the MCP restart it in a loop).
Once connected the driver re-arms a unit that fell silent or was power cycled and the serial link
reopens a vanished port. A unit silent for :data:`SILENT_AFTER_S` is logged once and nothing is
published while it is silent (never stale data); its return is logged too. Across such a gap the
heading keeps integrating the filtered z rate (trapezoidal over the gap, as the filter does), so
theta stays relative to the starting orientation.
"""

from __future__ import annotations

import math
import sys
import time

from wurde_core import CommsManager, Logger

from ..errors import DriverError
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.retry import RetryGate
from ..ports.serial_link import SerialLink
from ..ros_std_covariance import ImuNoise
from ..streams.dmu import DmuStreams
from .config import DmuDevice, load_dmu_config
from .device import DmuDriver

__all__ = ['DmuModule', 'DmuRunner', 'main']

#: Loop sleep and the longest poll: the DMU streams at up to ~100 Hz.
SLEEP_S = 0.01
#: Longest the loop blocks in one connection attempt (well under the 1 s heartbeat TTL).
CONNECT_TIMEOUT_S = 0.5
#: Seconds between two connection attempts while the unit is not there.
RETRY_S = 1.0
#: A unit that sent nothing for this long is silent (many packet periods).
SILENT_AFTER_S = 0.5


class DmuModule:
    """The module's work per loop turn: connect (again), poll, publish, watch for silence."""

    def __init__(self, device: DmuDevice, driver: DmuDriver, streams: DmuStreams,
                 logger: Logger) -> None:
        """Nothing is connected yet: the first :meth:`step` tries.

        :param device: the configured device (for messages).
        :param driver: the device layer (constructed, not yet connected).
        :param streams: the module's DMU streams.
        :param logger: where connection and silence changes are logged (once each).
        """
        self.device = device
        self.driver = driver
        self.streams = streams
        self.logger = logger
        self.connected = False
        self.silent = False
        self._failures = 0
        self._retry = RetryGate(RETRY_S)
        # The driver stamps samples with the monotonic clock; streams carry wall-clock time.
        self._to_wall = time.time() - time.monotonic()

    def step(self, timeout: float) -> int:
        """One turn: connect if needed, else poll up to ``timeout`` s; returns samples published.

        :param timeout: the longest poll in seconds.
        """
        if not self.connected:
            self._try_connect()
            return 0
        samples = self.driver.poll(timeout)
        if not samples:
            if not self.silent and self.driver.silent_for > SILENT_AFTER_S:
                self.silent = True
                self.logger.warn(f'DMU on {self.device.port} is silent (nothing for '
                                 f'{self.driver.silent_for:.1f} s); publishing nothing until '
                                 'it is back')
            return 0
        if self.silent:
            self.silent = False
            self.logger.notice(f'DMU on {self.device.port} is back')
        for sample in samples:
            self.streams.publish(sample, sample.stamp + self._to_wall)
        return len(samples)

    def _try_connect(self) -> None:
        if not self._retry.due(time.monotonic()):
            return
        try:
            self.driver.connect(CONNECT_TIMEOUT_S)
        except DriverError as error:
            self.driver.link.close()   # open afresh next time (the port may be replaced)
            if self._failures == 0:
                self.logger.warn(f'DMU not ready: {error}; trying again every {RETRY_S:g} s')
            self._failures += 1
            return
        self.connected = True
        self.logger.notice(f'DMU on {self.device.port} streaming ({self.device.mode.name.lower()} '
                           f'mode, {self.device.baud} baud, filter cut-off '
                           f'{self.device.cutoff:g} Hz)')

    def close(self) -> None:
        """Stop the stream and close the port (idempotent)."""
        self.driver.close()


#: The raw sample's noise for ``/N/imu``'s covariances: rate 0.1 deg/s, acceleration 10 mg,
#: roll and pitch 0.5 deg (1 sigma). Assumed, not measured: the DMU's manual is not at hand
#: (docs/protocols.md 7); put the unit's datasheet figures here.
NOISE = ImuNoise(rate=math.radians(0.1), accel=0.01 * 9.80665, angle=math.radians(0.5))


DmuRunner = DmuModule  # old name (docs/naming.md)


def main(argv: list[str] | None = None) -> int:
    """The ``dmu_module`` program: one ``<device>`` of dmu-config.xml as raw and filtered streams.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status.
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoDMU')
    device = configured_device(manager, argv, 'dmu-config.xml', load_dmu_config)
    streams = DmuStreams(manager.name, device.cutoff, noise=NOISE, mount=device.mount)
    runner = DmuModule(device, DmuDriver(SerialLink(device.port, device.baud), mode=device.mode),
                       streams, Logger(manager.name))
    streams.register(manager)
    manager.register_supplier(runner.logger)
    set_loop(manager, SLEEP_S)
    streams.publish_info()

    def step() -> None:
        runner.step(SLEEP_S)

    return run_loop(manager, step, runner.close)


if __name__ == '__main__':
    sys.exit(main())
