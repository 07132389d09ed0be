"""DriveProxy: Pluto's drive proxy (Pluto 5: "translates simple ... method calls into the necessary
sequence of ... messages") for WURDE programs.

Verbs write ``drive/command`` (cmdFlags 0/10 velocity, 1/11 regulator, -1 release) or the status
request that starts the thread; accessors read ``drive/status`` (Pluto 6.1).  Read the status before
continuing a command by hand: data[0..1] are the velocities the drive actually commands, which after
a timeout or a stop are not the ones last sent (the seed's reason for the status).
"""

from __future__ import annotations

from wurde_core import CommsManager

from .chain_proxy import ChainProxy
from .drive_command import COMMAND, STATUS

__all__ = ['DriveProxy']


class DriveProxy(ChainProxy):
    """The driveModule as seen from ``manager``: commands out, status in.

    ``code`` is element[0]: 0 normal, -1 timeout, -10 thread stopped, 1/2 front/back bumper, 3/4/5
    sonar front/back/sides (None before the first status).
    """

    def __init__(self, manager: CommsManager, *, queue_mode: bool = False) -> None:
        """Register ``drive/command`` and ``drive/status`` with ``manager``.

        :param manager: the program's manager.
        :param queue_mode: keep every status and echo (:meth:`update` returns them all), not the
            newest.
        """
        super().__init__(manager, COMMAND, STATUS, queue_mode=queue_mode)

    def velocity(self, tv: float, rv: float, *, sonar: bool = False) -> bool:
        """Drive at ``tv`` m/s and ``rv`` rad/s (cmdFlags 0, or 10 with sonar protection).

        :param tv: the linear velocity (m/s); the drive limits it to its ``max_tv``.
        :param rv: the angular velocity (rad/s); the drive limits it to its ``max_rv``.
        :param sonar: slow and stop by the base's sonar (cmdFlags 10).
        :returns: whether it went now (False: held until the driveModule reads commands).
        """
        return self._send(10 if sonar else 0, [tv, rv], [])

    def heading(self, speed: float, heading: float, *, sonar: bool = False) -> bool:
        """The regulator: turn smoothly to ``heading`` (rad, Localization/Pose frame) and hold it at
        ``speed`` m/s (cmdFlags 1, or 11 with sonar protection).

        :param speed: the linear speed (m/s) while turning and holding.
        :param heading: the heading (rad, Localization/Pose frame).
        :param sonar: slow and stop by the base's sonar (cmdFlags 11).
        :returns: whether it went now (False: held until the driveModule reads commands).
        """
        return self._send(11 if sonar else 1, [speed], [0.0, heading])

    def stop(self) -> bool:
        return self.velocity(0.0, 0.0)

    @property
    def refused(self) -> int:
        """element[1]: commands the drive refused so far."""
        return self.element[1] if len(self.element) > 1 else 0

    @property
    def ready(self) -> bool:
        """element[2]: the drive hears the base's sonar and the base reads its commands, so a
        command can move the robot now (False before the first status)."""
        return len(self.element) > 2 and self.element[2] == 1
