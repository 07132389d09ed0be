"""Pluto's DMUstate: low-pass filtered DMU rates and accelerations, integrated heading (pure).

Pluto Software Documentation 8.2: "There I low pass filter the velocity and acceleration. I then
integrate out the heading, theta, (position[0]). This becomes the estimated total rotation about
the vertical relative to the starting orientation. [...] The pitch and roll angles are as before
[...] The timestamp has been delayed somewhat to try and account for the filter delay."

Our choices (Pluto does not say which filter): a first-order low-pass with cut-off ``fc``, time
constant ``tau = 1 / (2 pi fc)``, discretised exactly for the actual sample interval ``dt``::

    y += (1 - exp(-dt / tau)) * (x - y)

so a unit step reaches 1 - 1/e (63.2 %) after ``tau`` seconds whatever the sample rate. The group
delay of a first-order low-pass at frequencies well below ``fc`` is ``tau``, hence
``filter_delay = 1 / (2 pi fc)`` is subtracted from each stamp. The heading theta integrates the
filtered z rate with the trapezoidal rule (a constant rate gives exactly rate * elapsed time) and
is never wrapped. The first sample initialises the filter (no start-up transient). A stamp that
does not advance leaves the state unchanged. Frames are the robot's (z up, x forward, y left).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Protocol

__all__ = ['DmuFilter', 'FilteredState', 'ImuSample']

_FILTERED = ('rate_x', 'rate_y', 'rate_z', 'accel_x', 'accel_y', 'accel_z')


class ImuSample(Protocol):
    """What the filter reads from a sample (e.g. :class:`~wurde_drivers.dmu.device.RawSample`)."""

    roll: float | None
    pitch: float | None
    rate_x: float
    rate_y: float
    rate_z: float
    accel_x: float
    accel_y: float
    accel_z: float


@dataclasses.dataclass(frozen=True)
class FilteredState:
    """Pluto's DMUstate: theta (heading about z, from start), phi (pitch about y), psi (roll about
    x) in rad; filtered rates (rad/s) and accelerations (m/s^2); ``stamp`` already moved back by
    the filter delay. ``phi`` and ``psi`` are None when the sensor gives no angles."""

    stamp: float
    theta: float
    phi: float | None
    psi: float | None
    rate_x: float
    rate_y: float
    rate_z: float
    accel_x: float
    accel_y: float
    accel_z: float


class DmuFilter:
    """First-order low-pass of rates and accelerations plus the integrated heading.

    :param cutoff_hz: the low-pass cut-off frequency in Hz (> 0).
    :raises ValueError: ``cutoff_hz`` is not a positive finite number.
    """

    def __init__(self, cutoff_hz: float) -> None:
        if not (math.isfinite(cutoff_hz) and cutoff_hz > 0):
            raise ValueError(f'cutoff_hz must be positive, got {cutoff_hz!r}')
        self.cutoff_hz = float(cutoff_hz)
        self.tau = 1.0 / (2.0 * math.pi * self.cutoff_hz)
        #: Seconds subtracted from each stamp: the filter's low-frequency group delay.
        self.filter_delay = self.tau
        self.reset()

    def reset(self) -> None:
        """Forget the filter state; the next sample starts again with theta = 0."""
        self._values: list[float] | None = None
        self._stamp = 0.0
        self.theta = 0.0

    def update(self, sample: ImuSample, stamp: float) -> FilteredState:
        """Filter one sample taken at ``stamp`` (seconds) and return the state."""
        raw = [float(getattr(sample, name)) for name in _FILTERED]
        if self._values is None:
            self._values = raw
            self._stamp = stamp
        else:
            dt = stamp - self._stamp
            if dt > 0:
                previous_rate_z = self._values[2]
                alpha = 1.0 - math.exp(-dt / self.tau)
                self._values = [y + alpha * (x - y) for x, y in zip(raw, self._values)]
                self.theta += 0.5 * (previous_rate_z + self._values[2]) * dt
                self._stamp = stamp
        return FilteredState(self._stamp - self.filter_delay, self.theta, sample.pitch,
                             sample.roll, *self._values)
