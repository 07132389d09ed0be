"""LocalProxy: the localModule's proxy (Pluto 3) — Pluto's ``loc_proxy`` for its five pose
interfaces (:class:`pluto_nav.loc_proxy.LocProxy`: ``get_pose(n)``, ``set_pose``, the setter)
with the module's own status, ``Localization/Status`` (FVectorState): element = [odometry fresh,
DMU fresh, setter, refused Post_Pose writes], data = [seconds since the last odometry, the Pose's
position standard deviation in m].
"""

from __future__ import annotations

from wurde_core import CommsManager
from wurde_core.interfaces import FVectorState

from pluto_nav.loc_proxy import LocProxy

__all__ = ['ALL_INTERFACES', 'LocalProxy']

#: The mask of the five interfaces (2**0 + ... + 2**4).
ALL_INTERFACES = 31
STATUS = 'Localization/Status'


class LocalProxy(LocProxy):
    """The localModule as seen from ``manager``: the interfaces of ``mask`` and the status."""

    def __init__(self, manager: CommsManager, mask: int = ALL_INTERFACES) -> None:
        """Read the pose interfaces of ``mask`` and ``Localization/Status``.

        :param manager: the program's manager.
        :param mask: which pose interfaces to read: bit n for interface n (0 Dead-Reckoning ...
            3 Pose); :data:`ALL_INTERFACES` all five.
        """
        super().__init__(manager, mask)
        self.status = FVectorState(STATUS)
        manager.register_consumer(self.status)
        self.element: list[int] = []
        self.data: list[float] = []

    def update(self) -> bool:
        held = super().update()
        while self.status.get_next_data():
            self.element = list(self.status.data.element)
            self.data = list(self.status.data.data)
        return held

    @property
    def odometry_fresh(self) -> bool | None:
        return bool(self.element[0]) if self.element else None

    @property
    def dmu_fresh(self) -> bool | None:
        return bool(self.element[1]) if len(self.element) > 1 else None

    @property
    def refused(self) -> int:
        """Post_Pose writes the localModule refused so far."""
        return self.element[3] if len(self.element) > 3 else 0
