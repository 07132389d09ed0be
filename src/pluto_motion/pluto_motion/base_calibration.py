"""The driveModule's start-up duty of Pluto 6.1: "The calibration data are read from a file and
written to the baseserver when the drive module is started" (file format and base request:
:mod:`pluto_nav.odometry_calibration`).

The request goes on the base's command stream, which the drive also writes velocities to every
loop; a request channel keeps one request for a reader that has not read yet, so the calibration
is sent again every :data:`RESEND_S` until the base's command data shows the scales in force[0..1].
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from wurde_core.interfaces import ActuatorState

from pluto_nav.odometry_calibration import CALIBRATE, Calibration

__all__ = ['BaseCalibration']

RESEND_S = 0.5


class BaseCalibration:
    """Set ``calibration`` in the base behind ``base`` (its ``<base>Command``), once confirmed."""

    def __init__(self, base: ActuatorState, calibration: Calibration, say: Callable[[str], object]) -> None:
        self.base, self.calibration, self.say = base, calibration, say
        self.confirmed = False
        self._sent = -math.inf

    def step(self) -> None:
        """Send (again) if due; check the base's command data for the scales."""
        if self.confirmed:
            return
        wanted = (self.calibration.distance, self.calibration.rotation)
        while self.base.get_next_data():
            force = list(self.base.data.force)
            if len(force) >= 2 and all(math.isclose(a, b, rel_tol=1e-5) for a, b in zip(force, wanted)):
                self.confirmed = True
                self.say(f'odometry calibration distance x{wanted[0]:.6f} rotation x{wanted[1]:.6f} set in the base')
                return
        if time.monotonic() - self._sent >= RESEND_S and self.base.peers('request'):
            req = self.base.requests
            req.cmd_flags.set_value(CALIBRATE)
            req.velocity.set_value([])
            req.force.set_value(list(wanted))
            self.base.publish_request()
            req.force.set_value([])
            self._sent = time.monotonic()
