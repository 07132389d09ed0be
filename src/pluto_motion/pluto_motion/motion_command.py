"""The motionModule's command and status codes (Pluto 6.3) and its rectangle.

``motion/command`` requests (ActuatorState): "The cmdFlags < 40 are simply passed thru to the avoid
module"; 42 moveto (position x, y); 43 investigate; 44 explore (rectangle b, h = velocity[0..1],
home = the current pose); 45 start/resume explore/goto; 46 set the rectangle (b, h = velocity[0..1],
home x, y = position[0..1], theta = force[0]; b = 0 removes it); -1 releases the robot (motion and
avoid threads stop).  "The same motion can then be resumed by sending cmdFlags=44" (6.3) and 45
("start/resume"): both resume; a 44 with no velocity values is that resume, with b, h it starts a
new explore.  :func:`parse_command` refuses anything else, and any value that is not finite, with
:class:`CommandRefused`.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['COMMAND', 'STATUS', 'CommandRefused', 'Kind', 'MotionCommand', 'Rectangle', 'parse_command',
           'AT_GOAL', 'BLOCKED', 'INVESTIGATE_DONE', 'MOVETO_SET', 'NEARING', 'UNREACHABLE', 'NO_MOVETO',
           'THREAD_STOPPED', 'IDLE_RECTANGLE', 'IDLE', 'SCANNING', 'FOLLOWING', 'APPROACHING', 'CIRCLING']

COMMAND = 'motion/command'
STATUS = 'motion/status'

#: element[2] (Pluto 6.3), and ours: 3 the moveto goal is unreachable on the map (the plan failed);
#: 4 the moveto waits, stopped, for something not on the map (a person in a door) to clear the way.
MOVETO_SET, NEARING, NO_MOVETO, AT_GOAL, INVESTIGATE_DONE, UNREACHABLE, BLOCKED = -1, -2, 0, 1, 2, 3, 4
#: element[3] (Pluto 6.3).
THREAD_STOPPED, IDLE_RECTANGLE, IDLE, SCANNING, FOLLOWING, APPROACHING, CIRCLING = -10, -1, 0, 1, 3, 11, 12


class CommandRefused(ValueError):
    """A ``motion/command`` request the motionModule does not execute; the message says why."""


class Kind(enum.Enum):
    RELEASE = 'release'
    PASS = 'pass'
    MOVETO = 'moveto'
    INVESTIGATE = 'investigate'
    EXPLORE = 'explore'
    RESUME = 'resume'
    SET_RECTANGLE = 'set rectangle'


@dataclasses.dataclass(frozen=True)
class Rectangle:
    """Pluto 6.3: "The home is a point at the center of one side (base) of the rectangle with theta
    pointing perpendicular to the side into the rectangle.  b is the distance from the home point to
    each of the sides perpendicular to the base, (ie. the base length is actually 2*b).  The height
    is then the length of the sides perpendicular to the base."  Borders count as inside."""

    b: float
    h: float
    x: float
    y: float
    theta: float

    def local(self, x: ArrayLike, y: ArrayLike) -> tuple[NDArray, NDArray]:
        """(u, v): u along theta (0 at the base, h at the far side), v to the left of it."""
        dx, dy = np.asarray(x, dtype=float) - self.x, np.asarray(y, dtype=float) - self.y
        c, s = math.cos(self.theta), math.sin(self.theta)
        return c * dx + s * dy, -s * dx + c * dy

    def contains(self, x: ArrayLike, y: ArrayLike, margin: float = 0.0) -> NDArray:
        """Whether points are inside (or within ``margin`` of the rectangle)."""
        u, v = self.local(x, y)
        eps = 1e-9 + margin
        return (u >= -eps) & (u <= self.h + eps) & (np.abs(v) <= self.b + eps)

    def world(self, u: float, v: float) -> tuple[float, float]:
        """The world point of rectangle coordinates (u, v)."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return self.x + c * u - s * v, self.y + s * u + c * v

    def corners(self) -> list[tuple[float, float]]:
        return [self.world(0, -self.b), self.world(0, self.b), self.world(self.h, self.b), self.world(self.h, -self.b)]


@dataclasses.dataclass(frozen=True)
class MotionCommand:
    """One accepted request; ``raw`` keeps the fields for a pass-through."""

    kind: Kind
    cmd_flags: int
    position: tuple[float, ...] = ()
    velocity: tuple[float, ...] = ()
    force: tuple[float, ...] = ()
    #: 46: the rectangle (None: removed); 44: b, h with home taken from the pose by the module.
    rectangle: Rectangle | None = None


def _finite(name: str, values: Sequence[float]) -> tuple[float, ...]:
    used = tuple(float(v) for v in values)
    if not all(math.isfinite(v) for v in used):
        raise CommandRefused(f'{name} not finite: {list(used)}')
    return used


def _need(name: str, values: tuple[float, ...], count: int, flags: int) -> tuple[float, ...]:
    if len(values) < count:
        raise CommandRefused(f'cmdFlags {flags} needs {name}[0..{count - 1}], got {list(values)}')
    return values[:count]


def parse_command(cmd_flags: int, position: Sequence[float], velocity: Sequence[float],
                  force: Sequence[float]) -> MotionCommand:
    """The command of one ``motion/command`` request.

    :raises CommandRefused: cmdFlags not -1, 0..39 or 42..46; a value not finite; a value the
        command needs missing; a rectangle with a negative b or a non-positive h.
    """
    p, v, f = _finite('position', position), _finite('velocity', velocity), _finite('force', force)
    if cmd_flags == -1:
        return MotionCommand(Kind.RELEASE, cmd_flags)
    if 0 <= cmd_flags < 40:
        return MotionCommand(Kind.PASS, cmd_flags, p, v, f)
    if cmd_flags == 42:
        return MotionCommand(Kind.MOVETO, cmd_flags, _need('position', p, 2, cmd_flags))
    if cmd_flags == 43:
        return MotionCommand(Kind.INVESTIGATE, cmd_flags)
    if cmd_flags == 45 or (cmd_flags == 44 and not v):
        return MotionCommand(Kind.RESUME, cmd_flags)
    if cmd_flags == 44:
        b, h = _need('velocity', v, 2, cmd_flags)
        if not (b > 0 and h > 0):
            raise CommandRefused(f'cmdFlags 44: the rectangle b, h must be positive, got {b}, {h}')
        return MotionCommand(Kind.EXPLORE, cmd_flags, velocity=(b, h), rectangle=Rectangle(b, h, 0.0, 0.0, 0.0))
    if cmd_flags == 46:
        b, h = _need('velocity', v, 2, cmd_flags)
        if b == 0:
            return MotionCommand(Kind.SET_RECTANGLE, cmd_flags, velocity=(b, h))
        if not (b > 0 and h > 0):
            raise CommandRefused(f'cmdFlags 46: b must be >= 0 and h > 0, got {b}, {h}')
        x, y = _need('position', p, 2, cmd_flags)
        (theta,) = _need('force', f, 1, cmd_flags)
        return MotionCommand(Kind.SET_RECTANGLE, cmd_flags, (x, y), (b, h), (theta,), Rectangle(b, h, x, y, theta))
    raise CommandRefused(f'cmdFlags {cmd_flags}: the motionModule takes -1, 0..39 (passed to avoid), 42..46')
