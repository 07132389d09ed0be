"""Helpers for in-process tests of a module: a Logger that keeps its lines, a rig that steps the
module on its own CommsManager beside a second manager supplying its inputs over real DDS, and a
rig whose second manager is a robot with stamped odometry and a laser."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, Logger, Pose, RobotObject, Time
from wurde_core.interfaces import Egomotion, RangeFinder

#: The robot's clock: seconds since the epoch.
T0 = 1_800_000_000.0
#: The laser's beams, a half-degree fan of 180 degrees, and the one straight ahead.
BEAMS = 181
MIDDLE = 90


class Said(Logger):
    """The module's Logger (named ``name``), keeping what it was told to log in :attr:`lines`."""

    def __init__(self, name: str) -> None:
        super().__init__(name, stderr=False, use_syslog=False)
        self.lines: list[str] = []

    def log(self, level: int | str, message: str) -> bool:
        self.lines.append(message)
        return super().log(level, message)


class ModuleRig:
    """A module under test (:attr:`module`, with a ``step()``) on :attr:`manager`, its inputs
    supplied by :attr:`peer`; subclasses set the three and may :meth:`feed` each turn."""

    manager: CommsManager
    peer: CommsManager
    module: Any

    def feed(self) -> None:
        """Publish what the peer sends every turn (nothing by default)."""

    def turn(self) -> None:
        self.feed()
        self.peer.step()
        self.manager.step()
        self.module.step()
        self.manager.wait(0.02)

    def until(self, predicate: Callable[[], bool], what: str, timeout: float = 60.0) -> None:
        """Turn until ``predicate()`` holds; fail after ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while not predicate():
            assert time.monotonic() < deadline, f'{what}: not within {timeout} s'
            self.turn()


class StampedRig(ModuleRig):
    """A :class:`ModuleRig` whose :attr:`peer` (``name``) is a robot supplying odometry on
    ``motion`` and a laser 0.2 m ahead of its centre on ``laser``, both stamped with the robot's
    clock by the test, and the objects in ``others`` (stamped by the test too)."""

    def __init__(self, name: str, motion: str, laser: str, others: tuple[RobotObject, ...] = ()) -> None:
        self.peer = CommsManager(name)
        self.peer.set_no_sleep()
        self.peer.set_no_heartbeat()
        self.odometry = Egomotion(motion)
        self.laser = RangeFinder(laser)
        for obj in (self.odometry, self.laser, *others):
            obj.set_auto_timestamp(False)
            self.peer.register_supplier(obj)
        info = self.laser.info
        info.theta_offset.set_value(-math.pi / 2)
        info.theta_separation.set_value(math.pi / (BEAMS - 1))
        info.x_offset.set_value(0.2)
        info.y_offset.set_value(0.0)
        info.max_range.set_value(8.0)
        self.laser.publish_info()

    def pose(self, stamp: float, theta: float) -> None:
        """Odometry at ``stamp``: the robot at the origin, heading ``theta``."""
        self.odometry.data.location = Pose(0.0, 0.0, theta)
        self.odometry.data.timestamp = Time(stamp)
        self.odometry.publish_data()

    def scan(self, stamp: float, ahead: float) -> None:
        """A scan with one point, ``ahead`` m straight ahead of the laser."""
        ranges = [9.0] * BEAMS
        ranges[MIDDLE] = ahead
        self.laser.data.ranges = ranges
        self.laser.data.timestamp = Time(stamp)
        self.laser.publish_data()

    def close(self) -> None:
        self.peer.clean_up()
        self.manager.clean_up()
