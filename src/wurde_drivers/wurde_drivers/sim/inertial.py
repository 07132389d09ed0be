"""The dummy DMU and GPS: readings derived from the true motion (Pluto 8.2, 8.4).

- **DMU** (DMUState, robot frame x forward, y left, z up): the z rate is the true rotational
  velocity plus an optional constant bias and white noise; heading θ is that rate integrated from
  the start (total rotation, not wrapped, as Pluto's DMUstate); the world is flat, so pitch, roll
  and their rates are 0; accelerations are the translational acceleration along x, the centripetal
  ``tv × rv`` along y and gravity's reaction (+g) along z.
- **GPS**: the true position, plus white noise in metres, converted to latitude and longitude by a
  function of the caller (the local-frame conversion of ``wurde_drivers.gps.geo``), with the fix
  quality, satellites and HDOP from the configuration (Pluto 8.4: more than 5 satellites and
  quality 2 for sub-metre accuracy).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from ..dmu.sample import Inertial

__all__ = ['DmuModel', 'DmuReading', 'GpsModel', 'GpsReading', 'GRAVITY']

GRAVITY = 9.80665


@dataclasses.dataclass(frozen=True, kw_only=True)
class DmuReading(Inertial):
    """One dummy DMU sample (robot frame): the DMU's fields plus the true integrated heading."""

    theta: float

    @property
    def phi(self) -> float | None:
        """Pitch about y (Pluto's name)."""
        return self.pitch

    @property
    def psi(self) -> float | None:
        """Roll about x (Pluto's name)."""
        return self.roll


class DmuModel:
    """Integrates the (biased, noisy) z rate of the true motion into a heading."""

    def __init__(self, rng: np.random.Generator, *, rate_bias: float = 0.0,
                 rate_noise: float = 0.0, accel_noise: float = 0.0) -> None:
        self.rng = rng
        self.rate_bias = rate_bias
        self.rate_noise = rate_noise
        self.accel_noise = accel_noise
        self.theta = 0.0

    def _noise(self, sigma: float, n: int = 1) -> np.ndarray:
        return self.rng.normal(0.0, sigma, n) if sigma > 0.0 else np.zeros(n)

    def step(self, tv: float, rv: float, acceleration: float, dt: float) -> DmuReading:
        rate_z = rv + self.rate_bias + float(self._noise(self.rate_noise)[0])
        self.theta += rate_z * dt
        ax, ay, az = np.array([acceleration, tv * rv, GRAVITY]) + self._noise(self.accel_noise, 3)
        return DmuReading(theta=self.theta, roll=0.0, pitch=0.0, rate_x=0.0, rate_y=0.0, rate_z=rate_z,
                          accel_x=float(ax), accel_y=float(ay), accel_z=float(az))


@dataclasses.dataclass(frozen=True)
class GpsReading:
    latitude: float
    longitude: float
    altitude: float
    satellites: int
    quality: int
    hdop: float
    x: float
    y: float


class GpsModel:
    """GPS fixes of the true position; ``to_geodetic(x, y) -> (lat, lon)`` names the frame."""

    def __init__(self, rng: np.random.Generator, to_geodetic: Callable[[float, float], tuple[float, float]],
                 *, noise_m: float = 0.0, altitude: float = 0.0, satellites: int = 8,
                 quality: int = 2, hdop: float = 0.9) -> None:
        self.rng = rng
        self.to_geodetic = to_geodetic
        self.noise_m = noise_m
        self.altitude = altitude
        self.satellites = satellites
        self.quality = quality
        self.hdop = hdop

    def fix(self, x: float, y: float) -> GpsReading:
        if self.noise_m > 0.0:
            dx, dy = self.rng.normal(0.0, self.noise_m, 2)
            x, y = x + float(dx), y + float(dy)
        lat, lon = self.to_geodetic(x, y)
        return GpsReading(lat, lon, self.altitude, self.satellites, self.quality, self.hdop, x, y)
