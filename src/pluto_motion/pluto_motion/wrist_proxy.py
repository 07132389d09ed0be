"""WristProxy: Pluto's wrist proxy (Pluto 8.3) — point the pan/tilt wrist, read where it is.

"There is one command interface and one state interface. They both are of the type ActuatorState_i.
The position, velocity and acceleration vectors are (pan, tilt) in rads, rad/sec, rads/(sec*sec).
One must set both the velocity and acceleration > 0 if you want the position to change. The proxy
and interface are the best manual."  The wrist module (real or dummy) named ``N`` has one
ActuatorState stream ``N``: requests are commands (cmdFlags < 0 halts), the info the command
being executed, the data the state.
"""

from __future__ import annotations

from wurde_core import CommsManager
from wurde_core.interfaces import ActuatorState

from .proxy import Proxy

__all__ = ['WristProxy']

#: Defaults of :meth:`WristProxy.move`: rad/s and rad/s^2 per axis (both > 0, as 8.3 requires).
SPEED, ACCELERATION = 0.5, 1.0


class WristProxy(Proxy):
    """The wrist ``name`` as seen from ``manager``."""

    def __init__(self, manager: CommsManager, name: str = 'PlutoWrist') -> None:
        """Read and command the wrist's ActuatorState stream ``name``.

        :param manager: the program's manager.
        :param name: the wrist module's name (its stream).
        """
        super().__init__(manager)
        self.wrist = self._consume(ActuatorState(name))
        #: The newest state: (pan, tilt) rad and their velocities (None before the first).
        self.position: tuple[float, float] | None = None
        self.velocity: tuple[float, float] | None = None
        #: The command being executed: target (pan, tilt) (None before the wrist's info).
        self.target: tuple[float, float] | None = None

    def move(self, pan: float, tilt: float, speed: float = SPEED, acceleration: float = ACCELERATION) -> bool:
        """Turn to (``pan``, ``tilt``) rad at ``speed`` rad/s, accelerating at ``acceleration``.

        :param pan: the pan (rad, left > 0).
        :param tilt: the tilt (rad, down < 0).
        :param speed: each axis's speed (rad/s), above 0.
        :param acceleration: each axis's acceleration (rad/s²), above 0.
        :returns: whether it went now (False: held until the wrist reads commands).
        :raises ValueError: a speed or acceleration that is not above 0 (Pluto 8.3).
        """
        if speed <= 0 or acceleration <= 0:
            raise ValueError('the wrist moves only with speed and acceleration > 0 (Pluto 8.3)')
        req = self.wrist.requests
        req.cmd_flags.set_value(0)
        req.position.set_value([pan, tilt])
        req.velocity.set_value([speed, speed])
        req.acceleration.set_value([acceleration, acceleration])
        return self._request(self.wrist)

    def halt(self) -> bool:
        """Stop both axes where they are (cmdFlags -1)."""
        req = self.wrist.requests
        req.cmd_flags.set_value(-1)
        req.position.set_value([])
        req.velocity.set_value([])
        req.acceleration.set_value([])
        return self._request(self.wrist)

    def _take(self) -> None:
        while self.wrist.get_next_data():
            d = self.wrist.data
            if len(d.position) >= 2:
                self.position = (float(d.position[0]), float(d.position[1]))
            if len(d.velocity) >= 2:
                self.velocity = (float(d.velocity[0]), float(d.velocity[1]))
        while self.wrist.get_next_info():
            target = list(self.wrist.info.position.get_value())
            if len(target) >= 2:
                self.target = (float(target[0]), float(target[1]))
