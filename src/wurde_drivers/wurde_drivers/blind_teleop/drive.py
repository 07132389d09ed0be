"""What BlindTeleop asks for, from the raw axes, exactly as the guide's program computes it (WURDE
guide 1.1.5, lines 50-92).  Pure functions: no rclpy, no devices.

The OCR damaged the printed operators; read as the obvious C expressions:
``axis("translate")/32767.0%2.0%-1`` is ``... * 2.0 * -1``; ``axis("rotate")/32767.0 * 1.5%-1`` is
``... * 1.5 * -1``; ``axis("quicktilt")/32767.0%0.2`` is ``... * 0.2``; and the pan
``segment*(32767.0/6.0)/32767+«M_PI/4.0%-1`` is ``segment * (32767.0/6.0) / 32767 * M_PI/4.0 * -1``.
Pushing the translate stick forward gives a negative value on a Linux joystick, so forward is
``translate < 0``; a stick to the right is a positive rotate, which turns clockwise (negative).
"""

from __future__ import annotations

import dataclasses
import math

__all__ = ['Drive', 'drive', 'pan', 'tilt']

_FULL = 32767.0


@dataclasses.dataclass(frozen=True)
class Drive:
    """One turn's avoider command: ``verb`` is ``move`` (to the relative point ``goal``),
    ``rotate`` (by ``angle``) or ``stop``; ``goal`` is what the status line shows as the
    relative goal (the program sets it for a rotation too)."""

    verb: str
    goal: tuple[float, float] = (0.0, 0.0)
    angle: float = 0.0


def drive(translate: int, rotate: int) -> Drive:
    """Lines 50-75: forward past 15 % moves (steering past 10 %), else a rotate stick past 50 %
    turns a quarter, else stop."""
    if translate / _FULL < -0.15:
        x = translate / _FULL * 2.0 * -1
        y = rotate / _FULL * 1.5 * -1 if math.fabs(rotate / _FULL) > 0.1 else 0.0
        return Drive('move', (x, y))
    if math.fabs(rotate / _FULL) > 0.5:
        if rotate > 0:
            return Drive('rotate', (0.0, -3.14), -math.pi / 2)
        return Drive('rotate', (0.0, 3.14), math.pi / 2)
    return Drive('stop')


def tilt(quicktilt: int) -> float:
    """Lines 77-80: the tilt request (rad), 0 inside a 5 % dead band."""
    if math.fabs(quicktilt) / 32767 > 0.05:
        return quicktilt / _FULL * 0.2
    return 0.0


def pan(quickpan: int) -> float:
    """Lines 82-87: the pan request (rad) in sixths of a quarter turn (C's int truncation), 0
    inside a 5 % dead band."""
    if math.fabs(quickpan) / 32767 > 0.05:
        segment = int(quickpan / _FULL * 6.0)
        return segment * (_FULL / 6.0) / 32767 * math.pi / 4.0 * -1
    return 0.0
