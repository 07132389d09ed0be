"""The base's odometry calibration: scales applied to the distance driven and the angle turned.

Pluto 6.1 and 7.1: "the odometry calibration values used by the baseserver (read from a file by
the driveModule and then set in the baseserver)"; the seed names neither the call nor the values.
Here the base takes a request on its Pluto command stream ``<N>Command``: cmdFlags
:data:`CALIBRATE` with force[0..1] = (distance scale, rotation scale), each in
[:data:`MIN_SCALE`, :data:`MAX_SCALE`]; the base then reports odometry whose every increment of
distance and of heading is multiplied by them, and shows the scales in force[0..1] of its command
data (so a sender sees them taken).  Scales 1, 1 (the start) report the raw odometry unchanged.
"""

from __future__ import annotations

import math

__all__ = ['CALIBRATE', 'MAX_SCALE', 'MIN_SCALE', 'OdometryCalibration']

#: cmdFlags of the base command that sets the calibration (force[0..1] = the two scales).
CALIBRATE = 99
MIN_SCALE, MAX_SCALE = 0.5, 2.0


class OdometryCalibration:
    """Calibrated odometry from the raw one, increment by increment."""

    def __init__(self) -> None:
        self.distance = 1.0
        self.rotation = 1.0
        self._raw: tuple[float, float, float] | None = None
        self._pose: tuple[float, float, float] | None = None

    def problem(self, distance: float, rotation: float) -> str:
        """Why these scales cannot be set ('' when they can)."""
        for name, value in (('distance', distance), ('rotation', rotation)):
            if not (math.isfinite(value) and MIN_SCALE <= value <= MAX_SCALE):
                return f'{name} scale {value} is not in [{MIN_SCALE}, {MAX_SCALE}]'
        return ''

    def set(self, distance: float, rotation: float) -> None:
        """Use these scales from now on (the odometry goes on from where it is)."""
        self.distance, self.rotation = distance, rotation

    @property
    def identity(self) -> bool:
        return self.distance == 1.0 and self.rotation == 1.0 and self._pose is None

    def apply(self, x: float, y: float, theta: float, tv: float, rv: float) -> tuple[float, float, float, float, float]:
        """The calibrated (x, y, theta, tv, rv) for the raw ones: the raw step since the last call
        (distance along the heading, turn) scaled and added to the calibrated pose."""
        if self.identity:
            return x, y, theta, tv, rv
        if self._raw is None or self._pose is None:
            self._raw = self._pose = (x, y, theta)
            return x, y, theta, tv * self.distance, rv * self.rotation
        rx, ry, rt = self._raw
        turn = math.atan2(math.sin(theta - rt), math.cos(theta - rt))
        mid = rt + turn / 2
        step = (x - rx) * math.cos(mid) + (y - ry) * math.sin(mid)
        px, py, pt = self._pose
        turn *= self.rotation
        heading = pt + turn / 2
        step *= self.distance
        self._pose = (px + step * math.cos(heading), py + step * math.sin(heading), pt + turn)
        self._raw = (x, y, theta)
        return (*self._pose, tv * self.distance, rv * self.rotation)
