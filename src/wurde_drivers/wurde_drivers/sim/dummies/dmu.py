"""dummy_dmu: a simulated Crossbow DMU (Pluto 8.2) on the base's true motion.

It follows the base's ground truth (``<base name>Truth``, every simulation step) and publishes the
DMU streams of :mod:`wurde_drivers.streams.dmu` at the configured rate: the z rate is the true
rotational velocity plus the configured bias and noise, so the filtered heading drifts exactly as
a biased gyro's would.  A gap in the truth (the base stopped or restarting) is filled with samples
at the DMU's rate carrying the truth's mean motion over the gap, as a real DMU samples on: the
filter integrates rates, and the last rate across a gap of 5 s turned a resting robot by 98°
(issue 38).
"""

from __future__ import annotations

import math
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

#: Seconds between two truth samples (one every 20 ms simulation step) that are a gap to fill.
TRUTH_GAP_S = 0.1
#: Most samples a gap is filled with: 10 s at 50 Hz.  A longer gap's are further apart (the turn is
#: the same), so that a gap of minutes is not thousands of messages at once.
MAX_FILLS = 500


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
    last: tuple[float, float, float, float] | None = None       # stamp, x, y, theta of the truth
    next_publish: float | None = None

    def sample(tv: float, rv: float, acceleration: float, stamp: float, dt: float) -> None:
        nonlocal next_publish
        reading = model.step(tv, rv, acceleration, dt)
        if next_publish is None:
            next_publish = stamp
        if stamp >= next_publish - 1e-6:
            streams.publish(reading, stamp)
            next_publish += period * max(1, int((stamp - next_publish) / period) + 1)

    def step() -> None:
        nonlocal last
        while truth.get_next_data():
            d = truth.data
            now = (d.timestamp.get_seconds(), d.location.x(), d.location.y(), d.location.theta())
            if last is not None and now[0] > last[0]:
                gap = now[0] - last[0]
                fills = min(int(gap / period + 1e-6) - 1, MAX_FILLS) if gap > TRUTH_GAP_S else 0
                if fills > 0:       # the truth's mean motion over the gap, at the DMU's rate
                    dt = gap / (fills + 1)
                    tv = math.dist(now[1:3], last[1:3]) / gap
                    rv = math.remainder(now[3] - last[3], math.tau) / gap
                    for k in range(1, fills + 1):
                        sample(tv, rv, 0.0, last[0] + k * dt, dt)
                    gap = dt
                sample(d.tv, d.rv, d.acceleration, now[0], gap)
            if last is None or now[0] > last[0]:
                last = now

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
