"""The dummy SICK: geometry, units and timing of an LMS 2xx / PLS, ranges raycast from the map.

Geometry, units and timing are the real device's, from :mod:`wurde_drivers.sick.facts` (docs/protocols.md
1.6; Pluto 8.1): 181 values at 1° or 361 at 0.5° over 180°, counter-clockwise from the right (−90°)
to the left (+90°); cm mode reads up to 81.82 m in 1 cm steps, mm mode up to 8.182 m in 1 mm
steps, a PLS (0.5°, cm only) up to 50 m. A laser mounted
upside down (``inverted``) sees the world mirrored, so its beam order is reversed, as the real
driver must undo. A beam that hits nothing within the maximum range reads ``math.inf`` — the real
LMS's "value > maximum" code (8183) — so consumers cannot tell the dummy from the device.

Timing: one scan takes one mirror turn (75 Hz) per interlaced sweep (2 for 0.5°), and its telegram
takes ``10 × bytes / baud`` seconds on the serial line (10 bits a byte, 8N1); a scan can go out no
faster than the slower of the two. At 38400 baud a 361-value scan needs 190 ms on the line, which
is Pluto's "new scans about every 200 ms" (8.1).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..sick import codec, facts
from .world import World

__all__ = ['LaserGeometry', 'LaserModel']

_RESOLUTION = {'cm': 0.01, 'mm': 0.001}


@dataclasses.dataclass(frozen=True)
class LaserGeometry:
    """Configuration of one (dummy) laser; defaults are Pluto's sickModule (8.1)."""

    model: str = 'LMS'            # LMS or PLS
    count: int = 361              # 181 (1°) or 361 (0.5°)
    units: str = 'cm'             # cm (81.82 m) or mm (8.182 m)
    inverted: bool = False        # mounted upside down
    baudrate: int = 38400
    mount_x: float = 0.0          # m, position on the robot (forward)
    mount_y: float = 0.0          # m (left)
    mount_z: float = 0.4          # m above the floor (reported in the info)
    noise_sigma: float = 0.0      # m, Gaussian range noise (0: the seed's ideal dummy)

    def __post_init__(self) -> None:
        problem = facts.variant_error(self.model, self.count, self.units)
        if problem is not None:
            raise ValueError(problem)

    @property
    def fov(self) -> float:
        return math.pi

    @property
    def angle_step(self) -> float:
        return self.fov / (self.count - 1)

    @property
    def max_range(self) -> float:
        return facts.max_range_m(self.model, self.units)

    @property
    def resolution(self) -> float:
        return _RESOLUTION[self.units]

    @property
    def telegram_bytes(self) -> int:
        """Bytes of one B0 scan telegram on the line."""
        return codec.telegram_size(self.count)

    @property
    def scan_period_s(self) -> float:
        """Seconds between two scans at this baud rate (the mirror or the wire, the slower)."""
        return facts.scan_period_s(self.count, self.baudrate)

    @property
    def centre_offset_s(self) -> float:
        """Seconds from the middle of a scan to its last byte read, as the driver stamps it."""
        return facts.centre_offset_s(self.count, self.baudrate)

    def beam_angles(self) -> np.ndarray:
        """Beam directions on the robot, in the order the device sends them."""
        angles = -self.fov / 2 + self.angle_step * np.arange(self.count)
        return -angles if self.inverted else angles


class LaserModel:
    """Scans of one laser in a world: ``scan(pose)`` gives the ranges in the device's order."""

    def __init__(self, geometry: LaserGeometry, rng: np.random.Generator) -> None:
        self.geometry = geometry
        self.rng = rng
        self._angles = geometry.beam_angles()

    def origin(self, x: float, y: float, theta: float) -> tuple[float, float]:
        g = self.geometry
        return (x + g.mount_x * math.cos(theta) - g.mount_y * math.sin(theta),
                y + g.mount_x * math.sin(theta) + g.mount_y * math.cos(theta))

    def scan(self, world: World, x: float, y: float, theta: float, *,
             at: float | None = None) -> np.ndarray:
        """Ranges (m) from the true pose: quantised to the unit, ``inf`` past the maximum range.

        ``at``: the scan's stamp, where the world's people stand in the beams (every beam sees
        them as they are at the scan's centre time: the mirror sweeps a scan in one or two turns,
        13 or 27 ms, in which a person at 1.5 m/s moves 2 or 4 cm).
        """
        g = self.geometry
        ranges = np.asarray(world.raycast(self.origin(x, y, theta), theta + self._angles,
                                          g.max_range, at=at), dtype=float)
        hit = ranges < g.max_range
        if g.noise_sigma > 0.0:
            ranges = ranges + self.rng.normal(0.0, g.noise_sigma, ranges.shape)
            ranges = np.clip(ranges, 0.0, g.max_range)
        ranges = np.round(ranges / g.resolution) * g.resolution
        return np.where(hit, ranges, math.inf)
