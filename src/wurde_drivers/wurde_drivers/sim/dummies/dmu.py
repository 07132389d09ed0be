"""dummy_dmu: a simulated Crossbow DMU (Pluto 8.2) on the base's true motion.

It follows the base's ground truth (``<base name>Truth``, every simulation step) and publishes the
DMU streams of :mod:`wurde_drivers.streams.dmu` at the configured rate: the z rate is the true
rotational velocity plus the configured bias and noise, so the filtered heading drifts exactly as
a biased gyro's would.
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, Logger
from wurde_core.interfaces import Egomotion

from ...module_setup import run_loop, set_loop
from ...ros_std_covariance import ImuNoise
from ...streams.dmu import DmuStreams
from ..clock import make_rng
from ..config import DmuConfig
from ..inertial import DmuModel
from ..loading import read_sim_config


def main(argv: list[str] | None = None) -> int:
    """The ``dummy_dmu`` program: the sim-config's ``<dmu>`` on the simulated robot.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoDMU')
    config = read_sim_config(manager, argv)
    dc = config.dmu or DmuConfig()
    model = DmuModel(make_rng(config.seed, f'dmu:{manager.name}'), rate_bias=dc.rate_bias,
                     rate_noise=dc.rate_noise)
    # The simulator's own noise settings: rate noise as configured, exact accelerations and
    # angles (a flat world): their variances are the least ones.
    streams = DmuStreams(manager.name, dc.cutoff, noise=ImuNoise(rate=dc.rate_noise), mount=dc.mount)
    truth = Egomotion(config.base.truth_stream)
    truth.set_queue_mode(True)
    logger = Logger(manager.name)
    streams.register(manager)
    manager.register_consumer(truth)
    manager.register_supplier(logger)
    set_loop(manager, min(0.02, 0.5 / dc.rate / config.time_scale))
    streams.publish_info()
    period = 1.0 / dc.rate
    last_stamp: float | None = None
    next_publish: float | None = None

    def step() -> None:
        nonlocal last_stamp, next_publish
        while truth.get_next_data():
            stamp = truth.data.timestamp.get_seconds()
            if last_stamp is None or stamp <= last_stamp:
                last_stamp = stamp if last_stamp is None else last_stamp
                continue
            reading = model.step(truth.data.tv, truth.data.rv, truth.data.acceleration, stamp - last_stamp)
            last_stamp = stamp
            if next_publish is None:
                next_publish = stamp
            if stamp >= next_publish - 1e-6:
                streams.publish(reading, stamp)
                next_publish += period * max(1, int((stamp - next_publish) / period) + 1)

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
