"""The dummy base's own sensors: sonar ring, bumpers and battery (Pluto 5; WURDE 3.4.1, 3.4.3).

- **Sonar ring**: ``count`` transducers evenly spaced on a circle round the robot centre, each a
  cone of ``half_angle`` sampled by five rays whose shortest hit is the echo. Pluto's dummy sonar
  reads "just 8 meters" (5) when nothing echoes, so nothing in range reads ``max_range`` (8 m).
  Given a stamp, the rays meet the world's people where they are then.
- **Bumpers**: a front and a back bumper on a round footprint. A bumper is pressed while a wall, or
  (given a stamp) a person, is within ``contact_margin`` of the footprint on its half (in front of
  or behind the axle line). The base refuses a move that would push the footprint into a wall or a
  person and stops (see ``SimRobot``).
- **Battery**: a crude energy model — constant idle draw plus a draw proportional to speed —
  giving voltage, current, power and charge through the Power interface.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .world import World

#: Rays sampling each sonar cone.
_RAYS = 5

__all__ = ['Battery', 'BumperRing', 'SonarRing']


@dataclasses.dataclass(frozen=True)
class SonarRing:
    """A ring of sonars; defaults: 16 around an ATRV-sized body, 8 m, ±12.5° cones."""

    count: int = 16
    radius: float = 0.3
    max_range: float = 8.0
    half_angle: float = math.radians(12.5)
    mount_z: float = 0.3

    def angles(self) -> np.ndarray:
        return 2 * math.pi * np.arange(self.count) / self.count

    def ranges(self, world: World, x: float, y: float, theta: float, *,
               at: float | None = None) -> np.ndarray:
        """Range of each sonar (m): the nearest echo in its cone, ``max_range`` if none; ``at``:
        the stamp at which the world's people echo too."""
        headings = theta + self.angles()
        origins = np.stack([x + self.radius * np.cos(headings), y + self.radius * np.sin(headings)], axis=1)
        spread = np.linspace(-self.half_angle, self.half_angle, _RAYS)
        rays = (headings[:, None] + spread[None, :]).ravel()
        hits = world.raycast(np.repeat(origins, _RAYS, axis=0), rays, self.max_range, at=at)
        return np.minimum(hits.reshape(self.count, _RAYS).min(axis=1), self.max_range)


@dataclasses.dataclass(frozen=True)
class BumperRing:
    """Front and back bumpers on a round footprint of ``radius`` (m)."""

    radius: float = 0.35
    contact_margin: float = 0.01

    @property
    def reach(self) -> float:
        """How far from the centre something presses a bumper (m)."""
        return self.radius + self.contact_margin

    def pressed(self, world: World, x: float, y: float, theta: float, *,
                at: float | None = None) -> tuple[bool, bool]:
        """(front, back): which bumper touches the nearest wall, or (``at``: a stamp) a person
        then, at this pose."""
        wall = world.wall_within((x, y), self.reach)
        touches = [] if wall is None else [wall]
        if at is not None:
            touches += [closest for _, closest in world.people_within((x, y), self.reach, at)]
        aheads = [(p[0] - x) * math.cos(theta) + (p[1] - y) * math.sin(theta) for p in touches]
        return any(a >= 0.0 for a in aheads), any(a < 0.0 for a in aheads)


@dataclasses.dataclass
class Battery:
    """Energy model: ``idle_w`` always, plus ``w_per_mps`` × |tv| while driving."""

    nominal_voltage: float = 24.0
    low_voltage: float = 22.0
    critical_voltage: float = 21.0
    capacity_j: float = 24.0 * 3600 * 40   # 40 Ah at 24 V
    idle_w: float = 60.0
    w_per_mps: float = 200.0
    energy_j: float = dataclasses.field(default=-1.0)
    power_w: float = 0.0

    def __post_init__(self) -> None:
        if self.energy_j < 0:
            self.energy_j = self.capacity_j

    @property
    def charge(self) -> float:
        return max(0.0, self.energy_j / self.capacity_j)

    @property
    def voltage(self) -> float:
        """Linear from critical (empty) to 10 % above nominal (full)."""
        return self.critical_voltage + (1.1 * self.nominal_voltage - self.critical_voltage) * self.charge

    @property
    def current(self) -> float:
        return self.power_w / self.voltage if self.voltage > 0 else 0.0

    def drain(self, tv: float, dt: float) -> None:
        self.power_w = self.idle_w + self.w_per_mps * abs(tv)
        self.energy_j = max(0.0, self.energy_j - self.power_w * dt)
