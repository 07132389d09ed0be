"""The driveModule's command (Pluto 6.1): what an ActuatorState request on ``drive/command`` asks for.

"The cmdFlags should be set to 0, 1, 10 or 11 ... For cmdFlags 0 or 10 the velocity values will be
used to set the linear and angular velocities.  For cmdFlags 1 or 11 the position[1] is used to set
the direction ... that the robot will drive in.  While velocity[0] will set the linear velocity."
"If one adds 10 to the cmdFlags the drive adds sonar collision protection."  A negative cmdFlags
(-1) releases the robot: the drive thread stops, as the avoidModule's release_robot does (6.2).

:func:`parse_command` turns the request's fields into a :class:`DriveCommand` or raises
:class:`CommandRefused` with the reason (unknown cmdFlags, a missing array element, a value that is
not finite): the module counts and logs refusals and keeps executing the last good command.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Sequence

__all__ = ['COMMAND', 'RELEASE', 'STATUS', 'CommandRefused', 'DriveCommand', 'Mode', 'finite', 'parse_command']

#: The driveModule's streams (Pluto 4: "drive/command" "drive/status").
COMMAND = 'drive/command'
STATUS = 'drive/status'
#: cmdFlags that stops the drive thread (release the robot).
RELEASE = -1


class CommandRefused(ValueError):
    """A ``drive/command`` request the drive does not execute; the message says why."""


class Mode(enum.IntEnum):
    """The command type: the ones digit of cmdFlags."""

    VELOCITY = 0
    REGULATOR = 1


@dataclasses.dataclass(frozen=True)
class DriveCommand:
    """One accepted command.

    ``tv`` is the linear velocity (m/s) in both modes; ``rv`` the angular velocity (rad/s) in
    velocity mode; ``heading`` the direction to hold (rad, Localization/Pose frame) in regulator
    mode; ``sonar`` whether sonar protection is on (cmdFlags + 10).
    """

    mode: Mode
    tv: float
    rv: float = 0.0
    heading: float = 0.0
    sonar: bool = False

    @property
    def cmd_flags(self) -> int:
        return int(self.mode) + (10 if self.sonar else 0)


STOP = DriveCommand(Mode.VELOCITY, 0.0, 0.0)


def finite(name: str, values: Sequence[float], count: int) -> list[float]:
    """The first ``count`` of ``values`` as floats.

    :raises CommandRefused: fewer than ``count`` values, or one not finite.
    """
    if len(values) < count:
        raise CommandRefused(f'{name} needs {count} value(s), got {list(values)}')
    used = [float(v) for v in values[:count]]
    if not all(math.isfinite(v) for v in used):
        raise CommandRefused(f'{name} not finite: {used}')
    return used


def parse_command(cmd_flags: int, velocity: Sequence[float], position: Sequence[float]) -> DriveCommand | None:
    """The command of one request; None for a release (cmdFlags -1).

    :raises CommandRefused: cmdFlags not in (-1, 0, 1, 10, 11), or the values it needs missing or
        not finite.
    """
    if cmd_flags == RELEASE:
        return None
    if cmd_flags not in (0, 1, 10, 11):
        raise CommandRefused(f'cmdFlags {cmd_flags}: the drive takes 0, 1, 10, 11 (or -1 to release)')
    mode, sonar = Mode(cmd_flags % 10), cmd_flags >= 10
    if mode is Mode.VELOCITY:
        tv, rv = finite('velocity', velocity, 2)
        return DriveCommand(mode, tv, rv, sonar=sonar)
    (tv,) = finite('velocity', velocity, 1)
    heading = finite('position', position, 2)[1]
    return DriveCommand(mode, tv, heading=heading, sonar=sonar)
