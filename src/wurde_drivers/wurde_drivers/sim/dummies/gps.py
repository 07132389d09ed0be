"""dummy_gps: a simulated GPS receiver (Pluto 8.4) on the base's true position.

The map's frame is the local metric frame (x east, y north) of a tangent plane at the configured
latitude and longitude; a fix is the true position (plus the configured noise) converted to
latitude and longitude, with the configured satellites, quality and HDOP, at the configured rate.
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, Logger
from wurde_core.interfaces import Egomotion

from ...gps.geo import LocalFrame
from ...module_setup import run_loop, set_loop
from ...streams.gps import GpsStreams
from ..clock import make_rng
from ..config import GpsConfig
from ..inertial import GpsModel
from ..loading import read_sim_config


def main(argv: list[str] | None = None) -> int:
    """The ``dummy_gps`` program: the sim-config's ``<gps>`` on the simulated robot.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoGPS')
    config = read_sim_config(manager, argv)
    gc = config.gps or GpsConfig()
    frame = LocalFrame(gc.latitude, gc.longitude, gc.altitude)
    model = GpsModel(make_rng(config.seed, f'gps:{manager.name}'), lambda x, y: frame.from_xy(x, y),
                     noise_m=gc.noise, altitude=gc.altitude, satellites=gc.satellites,
                     quality=gc.quality, hdop=gc.hdop)
    streams = GpsStreams(manager.name, mount=gc.mount)
    truth = Egomotion(config.base.truth_stream)
    truth.set_queue_mode(True)     # every step, so fixes fall exactly on the period
    logger = Logger(manager.name)
    streams.register(manager)
    manager.register_consumer(truth)
    manager.register_supplier(logger)
    set_loop(manager, min(0.05, 0.5 / gc.rate / config.time_scale))
    streams.publish_info(latitude=gc.latitude, longitude=gc.longitude)
    period = 1.0 / gc.rate
    next_fix: float | None = None

    def step() -> None:
        nonlocal next_fix
        while truth.get_next_data():
            stamp = truth.data.timestamp.get_seconds()
            if next_fix is None:
                next_fix = stamp
            if stamp < next_fix - 1e-6:
                continue
            loc = truth.data.location
            fix = model.fix(loc.x(), loc.y())
            streams.publish_fix(latitude=fix.latitude, longitude=fix.longitude, altitude=fix.altitude,
                                satellites=fix.satellites, quality=fix.quality, hdop=fix.hdop,
                                fix_time=stamp % 86400.0, x=fix.x, y=fix.y, stamp=stamp)
            next_fix += period * max(1, int((stamp - next_fix) / period) + 1)

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
