"""WGS84 latitude/longitude to a local metric frame and back (Pluto's gpsmeter grid, doc 8.4).

The local frame is the tangent plane at an origin: x east, y north, up along the ellipsoid
normal (ENU), computed exactly through earth-centred earth-fixed (ECEF) coordinates on the WGS84
ellipsoid, so there is no small-area approximation in the conversion itself; a round trip is
exact to well under a millimetre at tens of kilometres. Pure Python (``math``), no I/O.
"""

from __future__ import annotations

import math

__all__ = ['A', 'E2', 'F', 'LocalFrame', 'ecef_to_geodetic', 'geodetic_to_ecef']

#: WGS84 semi-major axis (m) and flattening.
A = 6378137.0
F = 1.0 / 298.257223563
E2 = F * (2.0 - F)            # first eccentricity squared
B = A * (1.0 - F)             # semi-minor axis
_EP2 = E2 / (1.0 - E2)        # second eccentricity squared


def geodetic_to_ecef(latitude: float, longitude: float, altitude: float = 0.0
                     ) -> tuple[float, float, float]:
    """ECEF (m) of a point on the WGS-84 ellipsoid.

    :param latitude: degrees.
    :param longitude: degrees.
    :param altitude: metres above the ellipsoid.
    """
    lat, lon = math.radians(latitude), math.radians(longitude)
    sin_lat, cos_lat = math.sin(lat), math.cos(lat)
    n = A / math.sqrt(1.0 - E2 * sin_lat * sin_lat)
    return ((n + altitude) * cos_lat * math.cos(lon),
            (n + altitude) * cos_lat * math.sin(lon),
            (n * (1.0 - E2) + altitude) * sin_lat)


def ecef_to_geodetic(x: float, y: float, z: float) -> tuple[float, float, float]:
    """Latitude, longitude (degrees) and altitude above the ellipsoid (m) of an ECEF point.

    Bowring's parametric latitude as a start, refined by Newton-like iterations until the
    latitude changes by less than 1e-15 rad (sub-nanometre); three iterations usually suffice.

    :param x: m.
    :param y: m.
    :param z: m.
    """
    p = math.hypot(x, y)
    lon = math.atan2(y, x)
    if p < 1e-9:                                    # on the polar axis
        lat = math.copysign(math.pi / 2.0, z) if z else 0.0
        return math.degrees(lat), math.degrees(lon), abs(z) - B
    beta = math.atan2(z * A, p * B)
    lat = math.atan2(z + _EP2 * B * math.sin(beta) ** 3, p - E2 * A * math.cos(beta) ** 3)
    for _ in range(5):
        sin_lat = math.sin(lat)
        n = A / math.sqrt(1.0 - E2 * sin_lat * sin_lat)
        new = math.atan2(z + E2 * n * sin_lat, p)
        done = abs(new - lat) < 1e-15
        lat = new
        if done:
            break
    sin_lat, cos_lat = math.sin(lat), math.cos(lat)
    n = A / math.sqrt(1.0 - E2 * sin_lat * sin_lat)
    if abs(cos_lat) > 1e-3:
        altitude = p / cos_lat - n
    else:
        altitude = z / sin_lat - n * (1.0 - E2)
    return math.degrees(lat), math.degrees(lon), altitude


class LocalFrame:
    """The ENU tangent frame at ``latitude``, ``longitude`` (degrees), ``altitude`` (m).

    :meth:`to_xy` / :meth:`from_xy` are the 2-D grid Pluto's modules use (points taken at a
    given altitude, the origin's by default); :meth:`to_enu` / :meth:`from_enu` are the full
    3-D transform.
    """

    def __init__(self, latitude: float, longitude: float, altitude: float = 0.0) -> None:
        """The frame with its origin here.

        :param latitude: degrees, -90 to 90.
        :param longitude: degrees.
        :param altitude: metres above the ellipsoid.
        :raises ValueError: a value out of range or not finite.
        """
        if not (math.isfinite(latitude) and -90.0 <= latitude <= 90.0
                and math.isfinite(longitude) and math.isfinite(altitude)):
            raise ValueError(f'bad origin: {latitude}, {longitude}, {altitude}')
        self.latitude = latitude
        self.longitude = longitude
        self.altitude = altitude
        lat, lon = math.radians(latitude), math.radians(longitude)
        self._sin_lat, self._cos_lat = math.sin(lat), math.cos(lat)
        self._sin_lon, self._cos_lon = math.sin(lon), math.cos(lon)
        self._origin = geodetic_to_ecef(latitude, longitude, altitude)

    def __repr__(self) -> str:
        return f'LocalFrame({self.latitude!r}, {self.longitude!r}, {self.altitude!r})'

    def to_enu(self, latitude: float, longitude: float, altitude: float
               ) -> tuple[float, float, float]:
        """East, north, up (m) of a point from the origin.

        :param latitude: degrees.
        :param longitude: degrees.
        :param altitude: metres above the ellipsoid.
        """
        x, y, z = geodetic_to_ecef(latitude, longitude, altitude)
        dx, dy, dz = x - self._origin[0], y - self._origin[1], z - self._origin[2]
        sl, cl, so, co = self._sin_lat, self._cos_lat, self._sin_lon, self._cos_lon
        east = -so * dx + co * dy
        north = -sl * co * dx - sl * so * dy + cl * dz
        up = cl * co * dx + cl * so * dy + sl * dz
        return east, north, up

    def from_enu(self, east: float, north: float, up: float) -> tuple[float, float, float]:
        """Latitude, longitude (degrees) and altitude (m) of an ENU point.

        :param east: m from the origin.
        :param north: m.
        :param up: m.
        """
        sl, cl, so, co = self._sin_lat, self._cos_lat, self._sin_lon, self._cos_lon
        dx = -so * east - sl * co * north + cl * co * up
        dy = co * east - sl * so * north + cl * so * up
        dz = cl * north + sl * up
        return ecef_to_geodetic(self._origin[0] + dx, self._origin[1] + dy, self._origin[2] + dz)

    def to_xy(self, latitude: float, longitude: float, altitude: float | None = None
              ) -> tuple[float, float]:
        """x east, y north (m) of a point on the grid.

        :param latitude: degrees.
        :param longitude: degrees.
        :param altitude: metres above the ellipsoid; None: the origin's.
        """
        east, north, _ = self.to_enu(latitude, longitude,
                                     self.altitude if altitude is None else altitude)
        return east, north

    def from_xy(self, x: float, y: float, altitude: float | None = None) -> tuple[float, float]:
        """Latitude, longitude of a grid point -- the inverse of :meth:`to_xy`.

        The tangent plane leaves the ellipsoid as it goes out (about 8 m at 10 km), so the point
        is found along the frame's up axis; a few Newton steps make its altitude exact.

        :param x: m east of the origin.
        :param y: m north.
        :param altitude: metres above the ellipsoid; None: the origin's.
        """
        height = self.altitude if altitude is None else altitude
        up = 0.0
        latitude = longitude = 0.0
        for _ in range(6):
            latitude, longitude, reached = self.from_enu(x, y, up)
            error = reached - height
            if abs(error) < 1e-9:
                break
            # d(altitude)/d(up) is the cosine between the two normals, ~1 near the origin
            up -= error / max(0.5, self._normal_cosine(latitude, longitude))
        return latitude, longitude

    def _normal_cosine(self, latitude: float, longitude: float) -> float:
        lat, lon = math.radians(latitude), math.radians(longitude)
        return (math.cos(lat) * math.cos(lon) * self._cos_lat * self._cos_lon
                + math.cos(lat) * math.sin(lon) * self._cos_lat * self._sin_lon
                + math.sin(lat) * self._sin_lat)
