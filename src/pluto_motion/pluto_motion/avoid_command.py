"""The avoidModule's command (Pluto 6.2): what an ActuatorState request on ``avoidance/command`` asks for.

"The cmdFlags are comprised of two parts, the command type and the avoidance.  These correspond to the
ones and tens digit in the cmdFlags=10*A+T."  A (avoidance): 0 none, 1 sonar (the drive's +10), 2 laser
(the avoidModule's own protection), 3 both.  T (type):

=== ============ ==================================================================================
 T  type         fields
=== ============ ==================================================================================
 0  velocity     velocity[0] m/s, velocity[1] rad/s (passed to the drive as cmdFlags 0/10)
 1  regulator    velocity[0] speed, position[1] heading (rad, Localization/Pose frame; drive 1/11)
 2  goto         position[0..1] goal x, y (m, Localization/Pose frame); velocity[0..1] the maximum
                 linear (m/s) and angular (rad/s) velocity, both > 0; force[0] goal strength
                 (optional, 1 by default, > 0: above 1 weaker avoidance, below 1 stronger)
 3  wall follow  velocity[0] speed along the wall (m/s, >= 0); position[0] the distance (m) to keep
                 between the camera and the wall on the left (optional; absent or 0: the default)
=== ============ ==================================================================================

cmdFlags -1 releases the robot (the avoid thread stops).  Anything else, a missing field or a value
that is not finite is refused whole by :func:`parse_command` (:class:`CommandRefused` with the
reason); the module counts and logs refusals and keeps executing the last good command.
"""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Sequence

from .drive_command import RELEASE, CommandRefused, finite

__all__ = ['COMMAND', 'RELEASE', 'STATUS', 'AvoidCommand', 'CommandRefused', 'Kind', 'parse_command']

#: The avoidModule's streams (Pluto 4: "avoidance/command" "avoidance/status").
COMMAND = 'avoidance/command'
STATUS = 'avoidance/status'


class Kind(enum.IntEnum):
    """The command type T: the ones digit of cmdFlags."""

    VELOCITY = 0
    REGULATOR = 1
    GOTO = 2
    WALL_FOLLOW = 3


@dataclasses.dataclass(frozen=True)
class AvoidCommand:
    """One accepted command.

    ``tv``/``rv``: velocity mode's velocities, the regulator's and the wall follow's speed (``tv``);
    ``heading``: the regulator's heading; ``goal``: the goto's (x, y); ``max_tv``/``max_rv``: the
    goto's limits; ``strength``: the goto's force[0]; ``distance``: the wall follow's distance
    (0: the default); ``sonar``/``laser``: the avoidance digit A.
    """

    kind: Kind
    sonar: bool = False
    laser: bool = False
    tv: float = 0.0
    rv: float = 0.0
    heading: float = 0.0
    goal: tuple[float, float] = (0.0, 0.0)
    max_tv: float = 0.0
    max_rv: float = 0.0
    strength: float = 1.0
    distance: float = 0.0

    @property
    def cmd_flags(self) -> int:
        return 10 * (int(self.sonar) + 2 * int(self.laser)) + int(self.kind)


def parse_command(cmd_flags: int, velocity: Sequence[float], position: Sequence[float],
                  force: Sequence[float] = ()) -> AvoidCommand | None:
    """The command of one request; None for a release (cmdFlags -1).

    :raises CommandRefused: cmdFlags not -1 or 10*A+T with A, T in 0..3, or the values the type
        needs missing, not finite or out of range.
    """
    if cmd_flags == RELEASE:
        return None
    if not 0 <= cmd_flags <= 33 or cmd_flags % 10 > 3:
        raise CommandRefused(f'cmdFlags {cmd_flags}: the avoidModule takes 10*A+T with A, T in 0..3 '
                             '(or -1 to release)')
    kind, avoid = Kind(cmd_flags % 10), cmd_flags // 10
    common = (kind, bool(avoid & 1), bool(avoid & 2))          # kind, sonar, laser
    if kind is Kind.VELOCITY:
        tv, rv = finite('velocity', velocity, 2)
        return AvoidCommand(*common, tv=tv, rv=rv)
    if kind is Kind.REGULATOR:
        (tv,) = finite('velocity', velocity, 1)
        return AvoidCommand(*common, tv=tv, heading=finite('position', position, 2)[1])
    if kind is Kind.GOTO:
        x, y = finite('position', position, 2)
        max_tv, max_rv = finite('velocity', velocity, 2)
        if max_tv <= 0 or max_rv <= 0:
            raise CommandRefused(f'goto velocity limits must be > 0, got {[max_tv, max_rv]}')
        strength = finite('force', force, 1)[0] if len(force) else 1.0
        if strength <= 0:
            raise CommandRefused(f'goto force[0] (goal strength) must be > 0, got {strength}')
        return AvoidCommand(*common, goal=(x, y), max_tv=max_tv, max_rv=max_rv, strength=strength)
    (tv,) = finite('velocity', velocity, 1)
    distance = finite('position', position, 1)[0] if len(position) else 0.0
    if tv < 0 or distance < 0:
        raise CommandRefused(f'wall follow needs speed >= 0 and distance >= 0, got {tv}, {distance}')
    return AvoidCommand(*common, tv=tv, distance=distance)
