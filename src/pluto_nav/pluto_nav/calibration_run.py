"""pose_i's odometry calibration against the wall in front (Pluto 7.1: the find-wall "is used by
the pose_i to set the odometry calibration values used by the baseserver ... The calibration needs
to be set after changes to tire pressure").

The seed gives no procedure; ours, with the robot facing a long wall with room behind it:

1. find the wall (gamma1, rho1, laser frame) and read the odometry o1 (``<base>Motion``);
2. back straight away from it ``distance`` m (odometry) through the driveModule, stop, find it
   again: rho2, o2.  A straight move by d along the heading changes rho by -d cos(gamma) whatever
   the laser's mounting, so the true distance is (rho1 - rho2) / cos(gamma1);
3. turn ``angle`` rad (odometry) on the spot, stop, find it again: gamma3, o3.  Turning by phi
   changes gamma by -phi, so the true angle is gamma2 - gamma3; then turn back.

The factors true / odometry multiply the calibration in use (force[0..1] of ``<base>Command``'s
data: the base reports calibrated odometry) into the new one.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable

from wurde_core import CommsManager, RunState
from wurde_core.interfaces import ActuatorState, Egomotion, FVectorState

from .odometry_calibration import Calibration

__all__ = ['CalibrationRun', 'Measured']

SPEED, TURN = 0.2, 0.3
#: Seconds between drive commands while moving (the drive times out after 4 s without one).
COMMAND_S = 0.2
#: Seconds of the base's odometry the robot must have stood before the wall is found again: the
#: find-wall takes the next scan the poseModule processes, and a loaded poseModule may still be
#: working through scans taken while the robot slowed down, and one such scan makes the measured
#: turn short.
STILL_S = 0.6


@dataclasses.dataclass(frozen=True)
class Measured:
    """What one run measured: the factors and the calibration they give."""

    true_distance: float
    odometry_distance: float
    true_angle: float
    odometry_angle: float
    old: Calibration
    new: Calibration


class CalibrationRun:
    """The procedure over the drive (``drive/command``, ``drive/status``) and the base's streams."""

    def __init__(self, manager: CommsManager, base: str, timeout: float) -> None:
        self.manager, self.timeout = manager, timeout
        self.drive = ActuatorState('drive/command')
        self.drive_status = FVectorState('drive/status')
        self.motion = Egomotion(f'{base}Motion')
        self.motion.set_queue_mode(True)
        self.command = ActuatorState(f'{base}Command')
        for obj in (self.drive, self.drive_status, self.motion, self.command):
            manager.register_consumer(obj)
        self.pose: tuple[float, float, float] | None = None
        self.moving = True
        #: The base's stamp of the first odometry message of the current standstill (None: moving).
        self.still_since: float | None = None
        self.stamp = 0.0
        self.calibration: Calibration | None = None

    def _take(self) -> None:
        while self.motion.get_next_data():
            d = self.motion.data
            self.pose = (d.location.x(), d.location.y(), d.location.theta())
            self.moving = d.tv != 0.0 or d.rv != 0.0
            self.stamp = d.timestamp.get_seconds()
            if self.moving:
                self.still_since = None
            elif self.still_since is None:
                self.still_since = self.stamp
        while self.command.get_next_data():
            force = list(self.command.data.force)
            self.calibration = Calibration(*force[:2]) if len(force) >= 2 else Calibration()

    def until(self, test: Callable[[], bool], every: Callable[[], None] | None = None) -> bool:
        deadline = time.monotonic() + self.timeout
        sent = -math.inf
        while True:
            self._take()
            if test():
                return True
            if time.monotonic() >= deadline or self.manager.run_update() != RunState.RUN:
                return False
            if every is not None and time.monotonic() - sent >= COMMAND_S:
                every()
                sent = time.monotonic()

    def _velocity(self, tv: float, rv: float) -> None:
        req = self.drive.requests
        req.cmd_flags.set_value(0)
        req.velocity.set_value([tv, rv])
        req.position.set_value([])
        self.drive.publish_request()

    def _stop(self) -> bool:
        """Stop and wait until the odometry says the robot has stood for :data:`STILL_S`."""
        self.moving, self.still_since = True, None
        return self.until(lambda: not self.moving and self.still_since is not None
                          and self.stamp - self.still_since >= STILL_S, lambda: self._velocity(0.0, 0.0))

    def ready(self) -> str:
        """'' once the drive reads commands and the base has been heard, else what is missing."""
        if not self.until(lambda: self.drive.peers('request') > 0 and self.drive_status.peers('request') > 0):
            return 'no driveModule reads drive/command'
        self.drive_status.requests.element.set_value([0])      # start the drive thread
        self.drive_status.publish_request()
        if not self.until(lambda: self.pose is not None):
            return 'no odometry from the base'
        if not self._stop():
            return 'the robot did not stop'
        # The base publishes its command state (with the calibration) when commanded.
        if not self.until(lambda: self.calibration is not None, lambda: self._velocity(0.0, 0.0)):
            return 'no command state from the base'
        return ''

    def run(self, find_wall: Callable[[], tuple[float, float] | str], distance: float,
            angle: float) -> Measured | str:
        """The procedure; its measurements, or what went wrong."""
        problem = self.ready()
        if problem:
            return problem
        assert self.pose is not None and self.calibration is not None
        old = self.calibration
        first = find_wall()
        if isinstance(first, str):
            return first
        o1 = self.pose
        heading = (math.cos(o1[2]), math.sin(o1[2]))

        def along() -> float:
            assert self.pose is not None
            return (self.pose[0] - o1[0]) * heading[0] + (self.pose[1] - o1[1]) * heading[1]

        if not self.until(lambda: along() <= -distance, lambda: self._velocity(-SPEED, 0.0)) or not self._stop():
            return 'the robot did not back away from the wall'
        o2, second = self.pose, find_wall()
        if isinstance(second, str):
            return second
        turned = lambda: math.atan2(math.sin(self.pose[2] - o2[2]), math.cos(self.pose[2] - o2[2]))  # noqa: E731
        if not self.until(lambda: turned() >= angle, lambda: self._velocity(0.0, TURN)) or not self._stop():
            return 'the robot did not turn'
        o3, third = self.pose, find_wall()
        if isinstance(third, str):
            return third
        back = o3[2] - angle

        def turned_back() -> float:
            assert self.pose is not None
            return math.atan2(math.sin(self.pose[2] - back), math.cos(self.pose[2] - back))

        self.until(lambda: turned_back() <= 0.0, lambda: self._velocity(0.0, -TURN))
        self._stop()
        (g1, r1), (g2, r2), (g3, _) = first, second, third
        true_d = (r1 - r2) / math.cos(g1)
        odo_d = (o2[0] - o1[0]) * heading[0] + (o2[1] - o1[1]) * heading[1]
        true_a = math.atan2(math.sin(g2 - g3), math.cos(g2 - g3))
        odo_a = math.atan2(math.sin(o3[2] - o2[2]), math.cos(o3[2] - o2[2]))
        new = old.then(true_d / odo_d, true_a / odo_a)
        return Measured(true_d, odo_d, true_a, odo_a, old, new)
