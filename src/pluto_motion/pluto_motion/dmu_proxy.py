"""DmuProxy: Pluto's DMU proxy (Pluto 8.2) — the inertial sensor's two interfaces.

"The DMUraw_state is just the data off the crossbow inertial sensor ... The raw data are really hard
to use right so use the DMUstate interface instead": the DMU module ``N`` supplies the filtered
DMUstate on ``N`` (theta the heading integrated since the start, phi pitch, psi roll; filtered rates
and accelerations) and the raw one on ``N/Raw``.  The sensor takes no commands.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from wurde_core import CommsManager
from wurde_core.interfaces import DMUState

from .proxy import Proxy

__all__ = ['DmuProxy', 'Inertial']


@dataclasses.dataclass(frozen=True)
class Inertial:
    """One DMU state: angles (rad), angular rates (rad/s) and accelerations (m/s^2), robot axes."""

    theta: float
    phi: float
    psi: float
    rates: tuple[float, float, float]
    accelerations: tuple[float, float, float]
    stamp: float


def _read(d: Any) -> Inertial:
    return Inertial(d.theta, d.phi, d.psi, (d.rate_x, d.rate_y, d.rate_z),
                    (d.accel_x, d.accel_y, d.accel_z), d.timestamp.get_seconds())


class DmuProxy(Proxy):
    """The DMU ``name`` as seen from ``manager``: :attr:`state` (filtered) and :attr:`raw`."""

    def __init__(self, manager: CommsManager, name: str = 'PlutoDMU') -> None:
        """Read the DMU's streams ``<name>`` (filtered) and ``<name>/Raw``.

        :param manager: the program's manager.
        :param name: the DMU module's name.
        """
        super().__init__(manager)
        self.filtered = self._consume(DMUState(name))
        self.raw_stream = self._consume(DMUState(f'{name}/Raw'))
        self.state: Inertial | None = None
        self.raw: Inertial | None = None

    def _take(self) -> None:
        while self.filtered.get_next_data():
            self.state = _read(self.filtered.data)
        while self.raw_stream.get_next_data():
            self.raw = _read(self.raw_stream.data)
