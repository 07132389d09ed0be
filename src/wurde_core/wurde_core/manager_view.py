"""What a RobotObject sees of the CommsManager it is registered with.

The objects need the module's name (auto-tag, lock owners), its ROS node (to create their
publishers and subscriptions), its run state (no user data flows outside Run) and a way to warn.
They see only this small protocol, never the manager itself, so that imports point one way:
the manager knows its objects, the objects know no manager.
"""

from __future__ import annotations

from typing import Any, Protocol

from .enums import RunState
from .timestamp import Timestamp


class ManagerView(Protocol):
    """The part of a CommsManager a RobotObject uses."""

    name: str
    node: Any
    state: RunState

    def log_warning(self, text: str) -> None:
        """Warn through the module's logger.

        :param text: the warning.
        """

    def now(self) -> Timestamp:
        """The module's time (auto-timestamps): wall clock, or /clock with use_sim_time."""

    def entities_changed(self) -> None:
        """An object's publishers or subscriptions were made anew."""
