"""Helpers for the driveModule tests: a simulated Pluto in a small walled room (exact odometry), the
dummy base and the driveModule as real processes, and a test-side module with a DriveProxy that also
records the simulator's truth and the base's command."""

from __future__ import annotations

import contextlib
import math
import os
import pathlib
import time
from collections.abc import Callable, Iterator
from typing import Any

from lxml import etree
from wurde_core import CommsManager
from wurde_core.interfaces import ActuatorState, Egomotion
from wurde_testing import ChildProcess, find_executable

from pluto_motion.drive_proxy import DriveProxy

ROOT = pathlib.Path(__file__).resolve().parents[3]
SIM_CONFIG = ROOT / 'config' / 'pluto' / 'sim-config.xml'

#: A 6 m x 4 m room; the robot starts in its middle facing east (+x): 2.65 m of floor ahead of its
#: 0.35 m radius, and as much behind.
ROOM = """<?xml version="1.0"?>
<map name="room" version="1.0">
  <bounds xmin="0" ymin="0" xmax="6" ymax="4"/>
  <polyline points="0,0 6,0 6,4 0,4" closed="true"/>
  <place name="start" x="3" y="2" theta="0"/>
</map>
"""


def room_config(directory: pathlib.Path) -> pathlib.Path:
    """config/pluto's sim-config with the room as map and exact odometry, in ``directory``."""
    tree = etree.parse(str(SIM_CONFIG))
    root = tree.getroot()
    for key in ('trans', 'rot', 'drift'):
        root.find('odometry-noise').set(key, '0')
    tree.write(str(directory / 'sim-config.xml'))
    (directory / 'map.xml').write_text(ROOM)
    return directory


def program(package: str, name: str, directory: pathlib.Path, *args: str) -> ChildProcess:
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    return ChildProcess([find_executable(package, name), *args], env=env)


@contextlib.contextmanager
def robot(directory: pathlib.Path, *drive_args: str) -> Iterator[dict[str, ChildProcess]]:
    """The dummy base (PlutoBase) and the driveModule, stopped at the end."""
    with program('wurde_drivers', 'dummy_base', directory, '-n', 'PlutoBase') as base, \
            program('pluto_motion', 'drive_module', directory, *drive_args) as drive:
        yield {'base': base, 'drive': drive}


class Driver:
    """The test's module: a DriveProxy, and every event of the truth and of the base's command."""

    def __init__(self) -> None:
        self.manager = CommsManager('DriveTest')
        self.manager.set_no_sleep()
        self.drive = DriveProxy(self.manager, queue_mode=True)
        self.truth = Egomotion('PlutoBaseTruth')
        self.base = ActuatorState('PlutoBaseCommand')
        for obj in (self.truth, self.base):
            obj.set_queue_mode(True)
            self.manager.register_consumer(obj)
        self.truths: list[Any] = []
        self.statuses: list[Any] = []
        #: Child processes whose early exit ends a wait at once (with their stderr).
        self.children: dict[str, ChildProcess] = {}
        self.base_states: list[Any] = []
        #: The drive's echo of every command it accepted (stamped by the drive).
        self.accepted: list[Any] = []

    def pump(self) -> None:
        self.manager.step()
        self.statuses.extend(self.drive.update())
        self.accepted.extend(self.drive.echoes())
        while self.truth.get_next_data():
            self.truths.append(self.truth.data.ros_message())
        while self.base.get_next_data():
            self.base_states.append(self.base.data.ros_message())

    def until(self, predicate: Callable[[], bool], what: str, timeout: float = 30.0,
              every: Callable[[], object] | None = None, period: float = 0.5) -> float:
        """Pump until ``predicate()``; ``every`` is called at most each ``period`` s (a command
        resent).  Returns the monotonic time the predicate first held, after one more pump (a
        predicate that polls a task takes statuses in that only the next pump reports)."""
        deadline = time.monotonic() + timeout
        sent = -math.inf
        while True:
            self.pump()
            if predicate():
                held = time.monotonic()
                self.pump()
                return held
            for name, child in self.children.items():
                if child.process.poll() is not None:
                    raise AssertionError(f'{what}: {name} exited ({child.process.returncode}): {child.stderr}')
            now = time.monotonic()
            if now > deadline:
                raise AssertionError(f'{what}: not within {timeout} s; status {self.drive.data} '
                                     f'{self.drive.element}, truth {self.pose}')
            if every is not None and now - sent >= period:
                every()
                sent = now
            self.manager.wait(0.05)

    @property
    def pose(self) -> tuple[float, float, float] | None:
        if not self.truths:
            return None
        loc = self.truths[-1].location
        return loc.x, loc.y, loc.theta

    @property
    def tv(self) -> float:
        return self.truths[-1].tv if self.truths else math.nan

    def close(self) -> None:
        self.manager.clean_up()


def seconds(message: Any) -> float:
    return message.header.stamp.sec + message.header.stamp.nanosec * 1e-9


def angle_error(a: float, b: float) -> float:
    return abs(math.atan2(math.sin(a - b), math.cos(a - b)))
