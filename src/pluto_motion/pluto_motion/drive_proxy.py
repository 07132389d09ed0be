"""DriveProxy: Pluto's drive proxy (Pluto 5: "translates simple ... method calls into the necessary
sequence of ... messages") for WURDE programs.

Verbs write ``drive/command`` (cmdFlags 0/10 velocity, 1/11 regulator, -1 release) or the status
request that starts the thread; accessors read ``drive/status`` (Pluto 6.1).  Read the status before
continuing a command by hand: data[0..1] are the velocities the drive actually commands, which after
a timeout or a stop are not the ones last sent (the seed's reason for the status).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, RunState
from wurde_core.interfaces import ActuatorState, FVectorState

from .drive_command import COMMAND, RELEASE, STATUS

__all__ = ['DriveProxy']


class DriveProxy:
    """The driveModule as seen from ``manager``: commands out, status in."""

    def __init__(self, manager: CommsManager, *, queue_mode: bool = False) -> None:
        """:param queue_mode: keep every status (:meth:`update` returns them all), not the newest,
            and every echo of an accepted command (``command.get_next_data()``)."""
        self.manager = manager
        self.command = ActuatorState(COMMAND)
        self.status = FVectorState(STATUS)
        self.command.set_queue_mode(queue_mode)
        self.status.set_queue_mode(queue_mode)
        manager.register_consumer(self.command)
        manager.register_consumer(self.status)
        self.data: list[float] = []
        self.element: list[int] = []

    # -- verbs -----------------------------------------------------------------------------------
    def _send(self, flags: int, velocity: list[float], position: list[float]) -> bool:
        req = self.command.requests
        req.cmd_flags.set_value(flags)
        req.velocity.set_value(velocity)
        req.position.set_value(position)
        return self.command.publish_request()

    def velocity(self, tv: float, rv: float, *, sonar: bool = False) -> bool:
        """Drive at ``tv`` m/s and ``rv`` rad/s (cmdFlags 0, or 10 with sonar protection)."""
        return self._send(10 if sonar else 0, [tv, rv], [])

    def heading(self, speed: float, heading: float, *, sonar: bool = False) -> bool:
        """The regulator: turn smoothly to ``heading`` (rad, Localization/Pose frame) and hold it at
        ``speed`` m/s (cmdFlags 1, or 11 with sonar protection)."""
        return self._send(11 if sonar else 1, [speed], [0.0, heading])

    def stop(self) -> bool:
        return self.velocity(0.0, 0.0)

    def release_robot(self) -> bool:
        """Stop the drive thread (cmdFlags -1): it stops the base and then leaves it alone."""
        return self._send(RELEASE, [], [])

    def start_activity(self) -> bool:
        """Start the drive thread (nothing happens when it runs)."""
        self.status.requests.element.set_value([0])
        return self.status.publish_request()

    # -- status ----------------------------------------------------------------------------------
    def update(self) -> list[Any]:
        """Take in what arrived; the status messages taken in, oldest first (empty: none)."""
        taken = []
        while self.status.get_next_data():
            self.data, self.element = list(self.status.data.data), list(self.status.data.element)
            taken.append(self.status.data.ros_message())
        return taken

    @property
    def velocities(self) -> tuple[float, float] | None:
        """data[0..1]: the (slowed-down) linear and angular velocity commanded now."""
        return (self.data[0], self.data[1]) if len(self.data) >= 2 else None

    @property
    def code(self) -> int | None:
        """element[0]: 0 normal, -1 timeout, -10 thread stopped, 1/2 front/back bumper, 3/4/5 sonar
        front/back/sides (None before the first status)."""
        return self.element[0] if self.element else None

    @property
    def refused(self) -> int:
        """element[1]: commands the drive refused so far."""
        return self.element[1] if len(self.element) > 1 else 0

    def wait_for(self, test: Callable[['DriveProxy'], bool], timeout: float) -> bool:
        """Run the manager's loop until ``test(self)`` holds; False after ``timeout`` s or on Quit."""
        deadline = time.monotonic() + timeout
        while True:
            self.update()
            if test(self):
                return True
            if time.monotonic() >= deadline or self.manager.run_update() != RunState.RUN:
                return False
            self.manager.wait(0.05)
