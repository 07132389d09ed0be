"""dummy_sick: Pluto's dummy SICK server (5): scans raycast in the map from the true pose.

Options: ``-c sim-config.xml`` and ``-n <laser name>`` (which ``<laser>`` of the config this is,
as the SICKServer chooses its device by ``-n``, WURDE 7.5). It follows the base's ground truth
(``<base name>Truth``) and publishes the same streams as the SICK driver
(:mod:`wurde_drivers.streams.laser`) at the real device's scan rate for the configured baud and
resolution, stamped with the scan's centre time and its arrival time at the serial port.  The
config's people stand in the beams where they are at the scan's centre time, a function of that
stamp alone (:mod:`wurde_drivers.sim.walk`): the base, another process, has them in the same place.
"""

from __future__ import annotations

import collections
import dataclasses
import math
import sys

from wurde_core import CommsManager, Logger
from wurde_core.interfaces import Egomotion
from wurde_idl.errors import ConfigError

from ...module_setup import exit_on_config_error, run_loop, set_loop
from ...streams.laser import LaserStreams
from ..clock import make_rng
from ..laser import LaserModel
from ..loading import load_sim, sim_config_path

#: Seconds of ground truth kept to find the pose at a scan's centre time.
HISTORY_S = 2.0


class TruthHistory:
    """The base's true poses by stamp; ``at(t)`` interpolates between the two around ``t``."""

    def __init__(self) -> None:
        self.poses: collections.deque[tuple[float, float, float, float]] = collections.deque()

    def add(self, stamp: float, x: float, y: float, theta: float) -> None:
        self.poses.append((stamp, x, y, theta))
        while self.poses and self.poses[0][0] < stamp - HISTORY_S:
            self.poses.popleft()

    @property
    def latest(self) -> float:
        return self.poses[-1][0] if self.poses else -math.inf

    def at(self, t: float) -> tuple[float, float, float]:
        """The pose at ``t``; the heading turns the short way between the two samples (across
        +-pi too: a robot turning past west between two samples faces west, not east)."""
        before = None
        for pose in self.poses:
            if pose[0] > t:
                if before is None:
                    return pose[1:]
                span = pose[0] - before[0]
                f = (t - before[0]) / span if span > 0 else 1.0
                turn = math.remainder(pose[3] - before[3], math.tau)
                return (before[1] + f * (pose[1] - before[1]), before[2] + f * (pose[2] - before[2]),
                        math.remainder(before[3] + f * turn, math.tau))
            before = pose
        assert before is not None
        return before[1:]


def main(argv: list[str] | None = None) -> int:
    """The ``dummy_sick`` program: the sim-config's ``<laser>`` named like the module.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoLaser')
    path = sim_config_path(manager, argv, '\n  -n NAME  the <laser> of the config to simulate')
    try:
        config, world, _ = load_sim(path)
        if manager.name not in config.lasers:
            raise ConfigError(path, None, f'no <laser name="{manager.name}"> (lasers: '
                                          f'{", ".join(sorted(config.lasers)) or "none"}); use -n')
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    geometry = config.lasers[manager.name]
    # The module publishes in the robot's order whatever the mounting, as the driver does.
    model = LaserModel(dataclasses.replace(geometry, inverted=False),
                       make_rng(config.seed, f'laser:{manager.name}'))
    logger = Logger(manager.name)
    streams = LaserStreams(manager.name)
    truth = Egomotion(config.base.truth_stream)
    truth.set_queue_mode(True)
    streams.register(manager)
    manager.register_consumer(truth)
    manager.register_supplier(logger)
    set_loop(manager, min(0.02, geometry.scan_period_s / config.time_scale / 2))
    streams.publish_info(count=geometry.count, max_range=geometry.max_range, mount_x=geometry.mount_x,
                         mount_y=geometry.mount_y, mount_z=geometry.mount_z,
                         scan_time=geometry.scan_period_s)
    history = TruthHistory()
    delay = geometry.centre_offset_s   # centre of the scan → last byte read, as the driver stamps
    next_centre: float | None = None
    logger.notice(f'{manager.name}: dummy {geometry.model} with {geometry.count} beams, '
                  f'{geometry.units}, one scan every {geometry.scan_period_s * 1000:.0f} ms')

    def step() -> None:
        nonlocal next_centre
        while truth.get_next_data():
            loc = truth.data.location
            history.add(truth.data.timestamp.get_seconds(), loc.x(), loc.y(), loc.theta())
        if not history.poses:
            return
        if next_centre is None:
            next_centre = history.latest
        while history.latest >= next_centre + delay:
            x, y, theta = history.at(next_centre)
            ranges = model.scan(world, x, y, theta, at=next_centre)
            streams.publish_scan(ranges, centre_stamp=next_centre, arrival_stamp=next_centre + delay)
            next_centre += geometry.scan_period_s

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
