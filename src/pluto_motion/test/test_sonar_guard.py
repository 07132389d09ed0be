"""The driveModule's sonar protection judges what lies in the way of the round footprint
(pluto_motion.sonar_guard), on a Pluto-like ring: 16 sonars on a 0.3 m radius, 12.5 degree cones."""

from __future__ import annotations

import math

import pytest

from pluto_motion.sonar_guard import BACK, FRONT, SonarGuard, ring_layout

HALF = 0.218
RING = ring_layout(16, 0.0, 2 * math.pi / 16, 0.3, 0.0)
FAR = 8.0


def echo(sensor: tuple[float, float, float], walls: list[tuple[str, float, float, float]]) -> float:
    """The nearest echo in the sensor's cone from axis-parallel wall segments ('y', value, lo, hi)."""
    x0, y0, bearing = sensor
    best = FAR
    for k in range(41):
        a = bearing + HALF * (2 * k / 40 - 1)
        c, s = math.cos(a), math.sin(a)
        for axis, value, lo, hi in walls:
            if axis == 'y' and abs(s) > 1e-9:
                t = (value - y0) / s
                if t > 0 and lo <= x0 + t * c <= hi:
                    best = min(best, t)
            if axis == 'x' and abs(c) > 1e-9:
                t = (value - x0) / c
                if t > 0 and lo <= y0 + t * s <= hi:
                    best = min(best, t)
    return best


def guard() -> SonarGuard:
    g = SonarGuard()
    g.set_layout(RING, HALF)
    return g


def test_a_door_a_robot_fits_through_slows_it_but_never_stops_it() -> None:
    # The robot's centre at every place along a 0.9 m door's passage (jambs 0.3 m deep at y = +-0.45).
    for x in [i * 0.05 for i in range(-20, 21)]:
        walls = [('y', 0.45, -x - 0.15, -x + 0.15), ('y', -0.45, -x - 0.15, -x + 0.15)]
        ranges = [echo(s, walls) for s in RING]
        tv, _ = guard().limit(0.4, ranges)
        assert tv >= 0.05, f'stopped {x:.2f} m before the door: {ranges}'


def test_a_box_ahead_slows_then_stops_and_code_three() -> None:
    g = guard()
    for free, allowed in ((1.5, (0.5, 0)), (0.5, None), (0.08, (0.0, FRONT))):
        ranges = [echo(s, [('x', 0.35 + free, -0.3, 0.3)]) for s in RING]
        tv, code = g.limit(0.5, ranges)
        if allowed is None:
            assert 0.0 < tv < 0.5 and code == FRONT
        else:
            assert (tv, code) == pytest.approx(allowed)


def test_backwards_the_back_sonars_judge_and_a_wall_beside_is_not_in_the_way() -> None:
    g = guard()
    behind = [echo(s, [('x', -0.35 - 0.05, -0.3, 0.3)]) for s in RING]
    assert g.limit(-0.3, behind) == (0.0, BACK)
    assert g.limit(0.3, behind) == (0.3, 0)                    # driving away from it
    # A wall 0.25 m beside the footprint: a cone cannot tell where in it the echo came from, so the
    # 22.5 degree sonar's echo might be in the way 0.8 m ahead: a slight slow-down, no more.
    beside = [echo(s, [('y', 0.6, -3.0, 3.0)]) for s in RING]
    assert 0.4 <= g.limit(0.5, beside)[0] <= 0.5
