"""The fields of one DMU sample, declared once: roll and pitch, three angular rates, three
accelerations (Pluto 8.2's DMUraw_state; the Crossbow packet's order).

The codec's packet (sensor frame), the driver's raw sample and the filtered state (robot frame)
and the dummy DMU's reading all extend :class:`Inertial`, and the filter and the stream contract
read the fields by the names listed here.  Pure Python: the simulator may use it.
"""

from __future__ import annotations

import dataclasses

__all__ = ['ACCEL_FIELDS', 'MOTION_FIELDS', 'RATE_FIELDS', 'Inertial']


@dataclasses.dataclass(frozen=True)
class Inertial:
    """``roll`` (about x) and ``pitch`` (about y) in rad, None when the sensor gives no angles
    (scaled mode); rates in rad/s; accelerations in m/s² (specific force)."""

    roll: float | None
    pitch: float | None
    rate_x: float
    rate_y: float
    rate_z: float
    accel_x: float
    accel_y: float
    accel_z: float


#: The rate fields, x y z.
RATE_FIELDS = ('rate_x', 'rate_y', 'rate_z')
#: The acceleration fields, x y z.
ACCEL_FIELDS = ('accel_x', 'accel_y', 'accel_z')
#: What the filter smooths and the streams copy: rates, then accelerations.
MOTION_FIELDS = RATE_FIELDS + ACCEL_FIELDS
