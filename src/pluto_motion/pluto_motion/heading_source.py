"""Where the driveModule's regulator reads the robot's heading: the theta of
:class:`pluto_motion.pose_source.PoseSource` (Localization/Pose, else Dead-Reckoning, else the base
odometry, each fall-back logged once)."""

from __future__ import annotations

from collections.abc import Callable

from wurde_core import CommsManager

from .pose_source import FRESH_S, PoseSource

__all__ = ['FRESH_S', 'HeadingSource']


class HeadingSource(PoseSource):
    """The robot's heading from the best fresh pose source."""

    def __init__(self, manager: CommsManager, base: str, warn: Callable[[str], object]) -> None:
        super().__init__(manager, base, warn, user='the regulator holds its heading')

    def heading(self) -> float | None:
        """The heading (rad) or None when no source is fresh."""
        pose = self.pose()
        return None if pose is None else pose[2]
