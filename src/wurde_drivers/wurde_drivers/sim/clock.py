"""Simulated time: a fixed step, a time scale, and one seeded random source per run.

The simulation advances in fixed steps of simulated time, so a run depends only on its seed and the
commands it gets, never on how busy the machine is (a run repeats exactly). The time scale says how
fast simulated time runs against the wall clock: 10 means ten simulated seconds per wall second.
Stamps are simulated time, anchored at the wall-clock time the simulation started, so at scale 1
they are ordinary wall-clock stamps.
"""

from __future__ import annotations

import numpy as np

__all__ = ['SimClock', 'make_rng']


def make_rng(seed: int, stream: str = '') -> np.random.Generator:
    """A random source for one part of the simulation (``stream`` keeps parts independent).

    The same seed and stream give the same numbers on every run and machine (numpy's PCG64).
    """
    extra = [ord(c) for c in stream]
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence([seed, *extra])))


class SimClock:
    """Simulated time advanced in steps of ``step_s``; ``wall_period_s`` is a step on the wall."""

    def __init__(self, *, step_s: float, time_scale: float = 1.0, start: float = 0.0) -> None:
        if step_s <= 0.0:
            raise ValueError('step_s must be positive')
        if time_scale <= 0.0:
            raise ValueError('time_scale must be positive')
        self.step_s = step_s
        self.time_scale = time_scale
        self.start = start
        self.steps = 0

    @property
    def elapsed(self) -> float:
        """Simulated seconds since the start (exact multiple of the step)."""
        return self.steps * self.step_s

    @property
    def now(self) -> float:
        """The simulated time as a stamp (s since the epoch)."""
        return self.start + self.elapsed

    @property
    def wall_period_s(self) -> float:
        """How long one step lasts on the wall clock."""
        return self.step_s / self.time_scale

    def tick(self) -> float:
        """Advance one step; returns the step length."""
        self.steps += 1
        return self.step_s
