"""WGS84 latitude and longitude to UTM easting, northing and zone: what the ``utmPose`` command
answers from the GPS (AU Robot Servers, "Coordinate systems": UTM is ``utmPose``).

The transverse Mercator series of Krüger to the fourth order (Karney 2011, eq. 35), good to well
under a millimetre within the zone; no grid exceptions (Norway, Svalbard) are applied.
"""

from __future__ import annotations

import dataclasses
import math

__all__ = ['UtmPoint', 'to_utm']

_A = 6378137.0                          # WGS84 semi-major axis (m)
_F = 1 / 298.257223563                  # WGS84 flattening
_K0 = 0.9996                            # UTM scale on the central meridian
_N = _F / (2 - _F)
_AA = _A / (1 + _N) * (1 + _N ** 2 / 4 + _N ** 4 / 64)
_ALPHA = (_N / 2 - 2 * _N ** 2 / 3 + 5 * _N ** 3 / 16 + 41 * _N ** 4 / 180,
          13 * _N ** 2 / 48 - 3 * _N ** 3 / 5 + 557 * _N ** 4 / 1440,
          61 * _N ** 3 / 240 - 103 * _N ** 4 / 140,
          49561 * _N ** 4 / 161280)
_E = math.sqrt(_F * (2 - _F))           # first eccentricity


@dataclasses.dataclass(frozen=True)
class UtmPoint:
    """A UTM position: easting and northing (m; northing + 10 000 km south of the equator)."""

    easting: float
    northing: float
    zone: int
    north: bool

    @property
    def zone_name(self) -> str:
        """``32N``, ``33S``."""
        return f'{self.zone}{"N" if self.north else "S"}'


def to_utm(latitude: float, longitude: float) -> UtmPoint:
    """The UTM position of ``latitude``, ``longitude`` (degrees, WGS84).

    :raises ValueError: not a position UTM covers (latitude outside -80..84, not finite).
    """
    if not (math.isfinite(latitude) and math.isfinite(longitude)) or not -80.0 <= latitude <= 84.0:
        raise ValueError(f'no UTM position for latitude {latitude}, longitude {longitude}')
    longitude = (longitude + 180.0) % 360.0 - 180.0
    zone = min(60, int((longitude + 180.0) // 6) + 1)
    lam = math.radians(longitude - (zone * 6 - 183))
    phi = math.radians(latitude)
    tau = math.tan(phi)
    sigma = math.sinh(_E * math.atanh(_E * tau / math.sqrt(1 + tau * tau)))
    tau_c = tau * math.sqrt(1 + sigma * sigma) - sigma * math.sqrt(1 + tau * tau)
    xi_p = math.atan2(tau_c, math.cos(lam))
    eta_p = math.asinh(math.sin(lam) / math.sqrt(tau_c * tau_c + math.cos(lam) ** 2))
    xi, eta = xi_p, eta_p
    for j, alpha in enumerate(_ALPHA, start=1):
        xi += alpha * math.sin(2 * j * xi_p) * math.cosh(2 * j * eta_p)
        eta += alpha * math.cos(2 * j * xi_p) * math.sinh(2 * j * eta_p)
    easting = 500000.0 + _K0 * _AA * eta
    northing = _K0 * _AA * xi
    return UtmPoint(easting, northing if latitude >= 0 else northing + 10_000_000.0, zone,
                    latitude >= 0)
