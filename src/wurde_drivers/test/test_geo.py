"""WGS84 to the local metric frame and back: known distances and round-trip accuracy."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.gps.geo import A, B, E2, LocalFrame, ecef_to_geodetic, geodetic_to_ecef


def test_ecef_of_known_points() -> None:
    assert geodetic_to_ecef(0.0, 0.0, 0.0) == pytest.approx((A, 0.0, 0.0))
    assert geodetic_to_ecef(0.0, 90.0, 100.0) == pytest.approx((0.0, A + 100.0, 0.0), abs=1e-6)
    assert geodetic_to_ecef(90.0, 0.0, 0.0) == pytest.approx((0.0, 0.0, B), abs=1e-6)
    assert ecef_to_geodetic(0.0, 0.0, -B - 5.0) == pytest.approx((-90.0, 0.0, 5.0))


@pytest.mark.parametrize('latitude, metres', [(0.0, 110574.3), (45.0, 111132.0), (89.0, 111693.3)])
def test_one_degree_of_latitude(latitude: float, metres: float) -> None:
    # Meridian degree lengths (standard WGS84 table): about 111 km, growing toward the poles.
    frame = LocalFrame(latitude, 10.0)
    _, north = frame.to_xy(latitude + 0.001, 10.0)
    assert north * 1000 == pytest.approx(metres, abs=2.0)
    # A whole degree in the tangent plane is the chord-like projection, ~111 km.
    _, north = frame.to_xy(latitude + 1.0 if latitude < 89 else latitude - 1.0, 10.0)
    assert abs(north) == pytest.approx(metres, rel=0.001)


@pytest.mark.parametrize('latitude', [0.0, 30.0, 60.0])
def test_one_degree_of_longitude(latitude: float) -> None:
    frame = LocalFrame(latitude, -120.0)
    east, north = frame.to_xy(latitude, -120.0 + 0.001)
    prime_vertical = A / math.sqrt(1 - E2 * math.sin(math.radians(latitude)) ** 2)
    expected = prime_vertical * math.cos(math.radians(latitude)) * math.pi / 180
    assert east * 1000 == pytest.approx(expected, abs=0.5)
    assert abs(north) < 1e-3
    assert expected == pytest.approx({0.0: 111319.5, 30.0: 96486.3, 60.0: 55800.0}[latitude],
                                     abs=1.0)


def test_axes_point_east_and_north() -> None:
    frame = LocalFrame(-33.86, 151.21, 20.0)
    east, north = frame.to_xy(-33.85, 151.21)
    assert north > 1000 and abs(east) < 1e-6
    east, north = frame.to_xy(-33.86, 151.22)
    assert east > 900 and abs(north) < 1.0
    assert frame.to_xy(-33.86, 151.21) == pytest.approx((0.0, 0.0), abs=1e-9)
    _, _, up = frame.to_enu(-33.86, 151.21, 30.0)
    assert up == pytest.approx(10.0)


@settings(max_examples=300, deadline=None)
@given(st.floats(-85, 85), st.floats(-180, 180), st.floats(-100, 4000),
       st.floats(0, 2 * math.pi), st.floats(0, 10000))
def test_round_trip_error_under_a_millimetre_at_10_km(lat0: float, lon0: float, alt0: float,
                                                     bearing: float, distance: float) -> None:
    frame = LocalFrame(lat0, lon0, alt0)
    x, y = distance * math.sin(bearing), distance * math.cos(bearing)
    latitude, longitude = frame.from_xy(x, y)
    back = frame.to_xy(latitude, longitude)
    assert math.hypot(back[0] - x, back[1] - y) < 1e-3
    # and from lat/lon: lat/lon -> x/y -> lat/lon
    again = frame.from_xy(*back)
    error_north = (again[0] - latitude) * 111e3
    error_east = (again[1] - longitude + 540) % 360 - 180
    assert abs(error_north) < 1e-3
    assert abs(error_east * 111e3 * math.cos(math.radians(latitude))) < 1e-3


@settings(max_examples=300, deadline=None)
@given(st.floats(-90, 90), st.floats(-180, 180), st.floats(-1000, 100000))
def test_ecef_round_trip(latitude: float, longitude: float, altitude: float) -> None:
    back = ecef_to_geodetic(*geodetic_to_ecef(latitude, longitude, altitude))
    assert back[0] == pytest.approx(latitude, abs=1e-9)
    if abs(latitude) < 89.9999:
        assert (back[1] - longitude + 540) % 360 - 180 == pytest.approx(0.0, abs=1e-9)
    assert back[2] == pytest.approx(altitude, abs=1e-4)


def test_bad_origins_are_refused() -> None:
    for origin in ((91.0, 0.0), (math.nan, 0.0), (0.0, math.inf)):
        with pytest.raises(ValueError):
            LocalFrame(*origin)
