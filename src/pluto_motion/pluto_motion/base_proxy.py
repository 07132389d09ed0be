"""BaseProxy: the baseserver's proxy (Pluto 2, 4: "It provides control of the motors, odometry,
sonar and bumpers data"; 6.1, 7.1: the odometry calibration "set in the baseserver").

The base module ``N`` (dummy or rFLEX): commands on ``NCommand`` (cmdFlags 0, velocity[0..1] =
linear, angular; cmdFlags 99 sets the odometry calibration, force[0..1] = distance and rotation
scales), odometry on ``NMotion``, sonar ``NSonar``, bumpers ``NBumpers``, battery ``NPower``.  The
base stops by itself when commands stop coming (its watchdog).
"""

from __future__ import annotations

from wurde_core import CommsManager
from wurde_core.interfaces import ActuatorState, Bumper, Egomotion, Power, RangeFinder

from pluto_nav.odometry_calibration import CALIBRATE, Calibration

from .proxy import Proxy

__all__ = ['BaseProxy']


class BaseProxy(Proxy):
    """The base ``name`` as seen from ``manager``."""

    def __init__(self, manager: CommsManager, name: str = 'PlutoBase') -> None:
        """Read the base's streams ``<name>Motion``, ``Sonar``, ``Bumpers``, ``Power``; write
        ``<name>Command``.

        :param manager: the program's manager.
        :param name: the base module's name.
        """
        super().__init__(manager)
        self.command = self._consume(ActuatorState(f'{name}Command'))
        self.motion = self._consume(Egomotion(f'{name}Motion'))
        self.sonar = self._consume(RangeFinder(f'{name}Sonar'))
        self.bumper_stream = self._consume(Bumper(f'{name}Bumpers'))
        self.power = self._consume(Power(f'{name}Power'))
        #: Odometry (x, y, theta) and (tv, rv), None before the first.
        self.pose: tuple[float, float, float] | None = None
        self.speeds: tuple[float, float] | None = None
        #: The velocities the base executes now and its calibration (its command data, which the
        #: base publishes when a command changes them: None before).
        self.velocities: tuple[float, float] | None = None
        self.calibration: Calibration | None = None
        self.ranges: list[float] = []
        self.bumpers: list[bool] = []
        self.voltage: float | None = None

    def velocity(self, tv: float, rv: float) -> bool:
        """Drive at ``tv`` m/s and ``rv`` rad/s (cmdFlags 0).

        :param tv: the linear velocity (m/s), straight to the base: no drive's guard.
        :param rv: the angular velocity (rad/s).
        :returns: whether it went now (False: held until the base reads commands).
        """
        req = self.command.requests
        req.cmd_flags.set_value(0)
        req.velocity.set_value([tv, rv])
        req.force.set_value([])
        return self._request(self.command)

    def stop(self) -> bool:
        return self.velocity(0.0, 0.0)

    def calibrate(self, calibration: Calibration) -> bool:
        """Set the odometry calibration (cmdFlags 99); :attr:`calibration` shows it once taken.

        :param calibration: the distance and rotation scales (true over raw odometry).
        :returns: whether it went now (False: held until the base reads commands).
        """
        req = self.command.requests
        req.cmd_flags.set_value(CALIBRATE)
        req.velocity.set_value([])
        req.force.set_value([calibration.distance, calibration.rotation])
        return self._request(self.command)

    def _take(self) -> None:
        while self.command.get_next_data():
            d = self.command.data
            if len(d.velocity) >= 2:
                self.velocities = (float(d.velocity[0]), float(d.velocity[1]))
            force = list(d.force)
            self.calibration = Calibration(*force[:2]) if len(force) >= 2 else Calibration()
        while self.motion.get_next_data():
            d = self.motion.data
            self.pose = (d.location.x(), d.location.y(), d.location.theta())
            self.speeds = (d.tv, d.rv)
        while self.sonar.get_next_data():
            self.ranges = [float(r) for r in self.sonar.data.ranges]
        while self.bumper_stream.get_next_data():
            self.bumpers = [bool(b) for b in self.bumper_stream.data.bumpers]
        while self.power.get_next_data():
            self.voltage = float(self.power.data.voltage)
