"""Driving a vector relative to the robot: the control law of the SynchroMover (WURDE 7.3).

A vector (magnitude m, angle rad counter-clockwise from straight ahead) given at some pose is
turned into a goal in the odometry frame once, so that the robot drives to where the vector
pointed when it was given, however it has moved since.  A vector of zero length with an angle
is a rotation on the spot by that angle.  A new vector replaces the old one (the guide: "when it
receives a new goal point, it overrides its current goal point").

The law is that of a differential or synchro drive: turn on the spot while the goal is more than
``turn_first`` off the heading, then drive with the heading error taken out over ``settle_s``
and the speed falling with the distance left, so that the robot stops on the goal rather than
overshooting it.
"""

from __future__ import annotations

import dataclasses
import math

from .scan_points import wrap

__all__ = ['MoverLimits', 'MoverOutput', 'VectorFollower', 'wrap']



@dataclasses.dataclass(frozen=True)
class MoverLimits:
    """Speeds and tolerances of the mover (m, rad, s)."""

    max_tv: float = 0.5
    max_rv: float = 1.0
    #: A goal nearer than this is reached.
    reach_m: float = 0.05
    #: A rotation within this of its heading is done.
    reach_rad: float = 0.03
    #: Turn on the spot before driving when the goal is this far off the heading.
    turn_first: float = 0.35
    #: Errors are taken out over this long (a gain of 1 / settle_s).
    settle_s: float = 0.7


@dataclasses.dataclass(frozen=True)
class MoverOutput:
    """One control step: the command and what is left to do."""

    tv: float
    rv: float
    distance: float
    angle: float
    done: bool


class VectorFollower:
    """Drives to the goal of the last vector given (see the module docstring)."""

    def __init__(self, limits: MoverLimits = MoverLimits()) -> None:
        self.limits = limits
        self.goal: tuple[float, float] | None = None
        self.heading: float | None = None

    @property
    def active(self) -> bool:
        """Whether there is a goal to drive to or a rotation to make."""
        return self.goal is not None or self.heading is not None

    def set_vector(self, pose: tuple[float, float, float], magnitude: float, angle: float) -> None:
        """Replace the goal with ``magnitude`` m in direction ``angle`` from ``pose`` (x, y, theta in
        the odometry frame); a zero magnitude turns the robot by ``angle``."""
        if not (math.isfinite(magnitude) and math.isfinite(angle)):
            raise ValueError(f'vector ({magnitude}, {angle}) is not finite')
        x, y, theta = pose
        direction = theta + angle
        if abs(magnitude) < self.limits.reach_m:
            self.goal, self.heading = None, wrap(direction)
        else:
            self.goal = (x + magnitude * math.cos(direction), y + magnitude * math.sin(direction))
            self.heading = None

    def set_goal(self, x: float, y: float) -> None:
        """Replace the goal with the point (x, y) of the odometry frame."""
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError(f'goal ({x}, {y}) is not finite')
        self.goal, self.heading = (x, y), None

    def stop(self) -> None:
        """Forget the goal: the next steps command zero."""
        self.goal = self.heading = None

    def _turn(self, error: float) -> float:
        limits = self.limits
        return max(-limits.max_rv, min(limits.max_rv, error / limits.settle_s))

    def step(self, pose: tuple[float, float, float], max_tv: float | None = None,
             max_rv: float | None = None) -> MoverOutput:
        """The command for ``pose``; a reached goal is forgotten (``done``).  ``max_tv`` and
        ``max_rv`` lower the limits for this step (a consumer's speed limits)."""
        limits = self.limits
        tv_cap = min(limits.max_tv, max_tv) if max_tv else limits.max_tv
        rv_cap = min(limits.max_rv, max_rv) if max_rv else limits.max_rv
        x, y, theta = pose
        if self.heading is not None:
            error = wrap(self.heading - theta)
            if abs(error) <= limits.reach_rad:
                self.stop()
                return MoverOutput(0.0, 0.0, 0.0, 0.0, True)
            rv = max(-rv_cap, min(rv_cap, self._turn(error)))
            return MoverOutput(0.0, rv, 0.0, error, False)
        if self.goal is None:
            return MoverOutput(0.0, 0.0, 0.0, 0.0, True)
        dx, dy = self.goal[0] - x, self.goal[1] - y
        distance = math.hypot(dx, dy)
        error = wrap(math.atan2(dy, dx) - theta)
        if distance <= limits.reach_m or (distance < 2 * limits.reach_m and abs(error) > math.pi / 2):
            self.stop()                    # there, or just past it: done, not a turn back
            return MoverOutput(0.0, 0.0, distance, 0.0, True)
        rv = max(-rv_cap, min(rv_cap, self._turn(error)))
        if abs(error) > limits.turn_first:
            return MoverOutput(0.0, rv, distance, error, False)
        tv = min(tv_cap, distance / limits.settle_s) * math.cos(error)
        return MoverOutput(tv, rv, distance, error, False)
