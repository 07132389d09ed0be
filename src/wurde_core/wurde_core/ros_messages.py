"""Small helpers for the standard ROS 2 messages the modules publish next to their streams:
header stamps from seconds and quaternions from Pluto's angles (shared by every package)."""

from __future__ import annotations

import math
from typing import Any

__all__ = ['quaternion', 'set_stamp']


def set_stamp(message: Any, seconds: float) -> None:
    """Set ``message.header.stamp`` (or a bare ``builtin_interfaces/Time``) from seconds.

    :param message: a message with a header, or a ``builtin_interfaces/Time``.
    :param seconds: seconds since the epoch (rounded to the nanosecond).
    """
    stamp = message.header.stamp if hasattr(message, 'header') else message
    whole = math.floor(seconds)
    nanosec = int(round((seconds - whole) * 1e9))
    if nanosec >= 1_000_000_000:
        whole, nanosec = whole + 1, nanosec - 1_000_000_000
    stamp.sec = int(whole)
    stamp.nanosec = nanosec


def quaternion(theta: float, phi: float = 0.0, psi: float = 0.0) -> tuple[float, float, float, float]:
    """(x, y, z, w) of the rotation theta about z, then phi about y, then psi about x (Pluto 3).

    :param theta: rad about z (the heading).
    :param phi: rad about y.
    :param psi: rad about x.
    """
    cz, sz = math.cos(theta / 2), math.sin(theta / 2)
    cy, sy = math.cos(phi / 2), math.sin(phi / 2)
    cx, sx = math.cos(psi / 2), math.sin(psi / 2)
    return (sx * cy * cz - cx * sy * sz, cx * sy * cz + sx * cy * sz,
            cx * cy * sz - sx * sy * cz, cx * cy * cz + sx * sy * sz)
