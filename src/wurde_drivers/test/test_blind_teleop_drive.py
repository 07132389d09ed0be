"""BlindTeleop's arithmetic, as the guide's printed program computes it (1.1.5, lines 50-87)."""

from __future__ import annotations

import math

import pytest
from wurde_drivers.blind_teleop.drive import Drive, drive, pan, tilt


@pytest.mark.parametrize('translate, rotate, expected', [
    (0, 0, Drive('stop')),
    (-4000, 0, Drive('stop')),                          # -0.12: inside the 15 % dead band
    (-32767, 0, Drive('move', (2.0, 0.0))),             # full forward: 2 m ahead
    (-16384, 3000, Drive('move', (16384 / 32767 * 2.0, 0.0))),    # steering inside 10 %
    (-16384, 32767, Drive('move', (16384 / 32767 * 2.0, -1.5))),  # right: goal to the right
    (-16384, -32767, Drive('move', (16384 / 32767 * 2.0, 1.5))),
    (32767, 32767, Drive('rotate', (0.0, -3.14), -math.pi / 2)),  # back + right: turn clockwise
    (0, -20000, Drive('rotate', (0.0, 3.14), math.pi / 2)),
    (0, 16000, Drive('stop')),                          # rotate needs more than 50 %
])
def test_drive(translate: int, rotate: int, expected: Drive) -> None:
    assert drive(translate, rotate) == expected


def test_pan_and_tilt() -> None:
    assert tilt(0) == 0.0 and tilt(1600) == 0.0          # 5 % dead band
    assert tilt(32767) == pytest.approx(0.2) and tilt(-16384) == pytest.approx(-0.1, abs=1e-4)
    assert pan(1600) == 0.0
    assert pan(32767) == pytest.approx(-math.pi / 4)     # six sixths of a quarter, clockwise
    assert pan(-32767) == pytest.approx(math.pi / 4)
    assert pan(5000) == 0.0                               # past the dead band, segment int(0.92) = 0
    assert pan(10000) == pytest.approx(-1 / 6 * math.pi / 4)   # segment int(1.83) = 1
    assert pan(-10000) == pytest.approx(1 / 6 * math.pi / 4)   # C truncates toward zero
