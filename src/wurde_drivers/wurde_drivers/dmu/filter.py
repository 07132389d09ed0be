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

from .sample import MOTION_FIELDS, Inertial

__all__ = ['DmuFilter', 'FilteredState']

_RATE_Z = MOTION_FIELDS.index('rate_z')


@dataclasses.dataclass(frozen=True, kw_only=True)
class FilteredState(Inertial):
    """Pluto's DMUstate: the :class:`~.sample.Inertial` fields with rates and accelerations
    filtered (roll and pitch as the sensor gave them), ``theta`` the heading about z since the
    start (rad) and ``stamp`` already moved back by the filter delay.  Pluto's names for the
    angles, ``phi`` (pitch about y) and ``psi`` (roll about x), are None without angles."""

    stamp: float
    theta: float

    @property
    def phi(self) -> float | None:
        return self.pitch

    @property
    def psi(self) -> float | None:
        return self.roll


class DmuFilter:
    """First-order low-pass of rates and accelerations plus the integrated heading."""

    def __init__(self, cutoff_hz: float) -> None:
        """Start empty: the first sample sets the state, with theta 0.

        :param cutoff_hz: the low-pass cut-off frequency in Hz (> 0).
        :raises ValueError: ``cutoff_hz`` is not a positive finite number.
        """
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

    def update(self, sample: Inertial, stamp: float) -> FilteredState:
        """Filter one sample and return the state.

        :param sample: robot frame (z up), SI units.
        :param stamp: when it was taken, seconds; the state's stamp is earlier by :attr:`filter_delay`.
        """
        raw = [float(getattr(sample, name)) for name in MOTION_FIELDS]
        if self._values is None:
            self._values = raw
            self._stamp = stamp
        else:
            dt = stamp - self._stamp
            if dt > 0:
                previous_rate_z = self._values[_RATE_Z]
                alpha = 1.0 - math.exp(-dt / self.tau)
                self._values = [y + alpha * (x - y) for x, y in zip(raw, self._values)]
                self.theta += 0.5 * (previous_rate_z + self._values[_RATE_Z]) * dt
                self._stamp = stamp
        return FilteredState(stamp=self._stamp - self.filter_delay, theta=self.theta,
                             roll=sample.roll, pitch=sample.pitch,
                             **dict(zip(MOTION_FIELDS, self._values)))
