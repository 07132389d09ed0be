"""Helpers for the pluto_nav tests: a simulated Pluto in tmp, its modules as real processes, and a
test-side module that drives the base and keeps every event of the streams it watches."""

from __future__ import annotations

import contextlib
import math
import os
import pathlib
import time
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from lxml import etree
from wurde_core import CommsManager
from wurde_core.interfaces import robot_object_class
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'
MAPS = ROOT / 'config' / 'maps'

#: config/pluto's movement chain: left out, since these tests drive the base themselves.
MOVEMENT_CHAIN = ('driveModule', 'avoidModule', 'motionModule', 'navigator', 'map_server')

#: Zero noise everywhere: the odometry and the DMU are exact, so dead reckoning must be too.
EXACT = {'odometry-noise': {'trans': '0', 'rot': '0', 'drift': '0'}, 'laser': {'noise': '0'},
         'dmu': {'rate-noise': '0'}}


def pluto_config(directory: pathlib.Path, *, map_file: pathlib.Path | None = None,
                 elements: dict[str, dict[str, str]] | None = None, top: dict[str, str] | None = None) -> pathlib.Path:
    """config/pluto copied to ``directory`` (map.xml a copy of ``map_file``), with changes."""
    directory.mkdir(parents=True, exist_ok=True)
    tree = etree.parse(str(PLUTO / 'sim-config.xml'))
    root = tree.getroot()
    for key, value in (top or {}).items():
        root.set(key, value)
    for tag, attributes in (elements or {}).items():
        node = root.find(tag)
        assert node is not None, tag
        for key, value in attributes.items():
            node.set(key, value)
    tree.write(str(directory / 'sim-config.xml'))
    (directory / 'map.xml').write_bytes((map_file or PLUTO / 'map.xml').read_bytes())
    config = etree.parse(str(PLUTO / 'mcp-config.xml'))
    for node in list(config.getroot().iter('module')):
        if node.get('name') in MOVEMENT_CHAIN:     # the localization tests drive the base themselves
            config.getroot().remove(node)
    config.write(str(directory / 'mcp-config.xml'))
    (directory / 'mcp-mappings.xml').write_bytes((PLUTO / 'mcp-mappings.xml').read_bytes())
    return directory


def module(package: str, name: str, directory: pathlib.Path, *args: str,
           env: dict[str, str] | None = None) -> ChildProcess:
    """A pluto_nav or wurde_drivers executable with ``directory`` as its config, log and data
    directory (the localModule's resume file goes there, not into the working directory), and
    ``env`` added to the environment."""
    environment = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory),
                       WURDE_DATA_DIR=str(directory))
    environment.update(env or {})
    return ChildProcess([find_executable(package, name), *args], env=environment)


DUMMIES = {'PlutoBase': 'dummy_base', 'PlutoLaser': 'dummy_sick', 'PlutoDMU': 'dummy_dmu',
           'PlutoWrist': 'dummy_wrist'}


@contextlib.contextmanager
def processes(directory: pathlib.Path, dummies: Sequence[str],
              *nav: tuple[str, Sequence[str]]) -> Iterator[dict[str, ChildProcess]]:
    """The named dummies and the pluto_nav executables ``(name, args)``, stopped at the end."""
    with contextlib.ExitStack() as stack:
        running = {}
        for name in dummies:
            running[name] = stack.enter_context(module('wurde_drivers', DUMMIES[name], directory, '-n', name))
        for executable, args in nav:
            running[executable] = stack.enter_context(module('pluto_nav', executable, directory, *args))
        yield running


class Watcher:
    """A module in the test process: consumes streams (queue mode) and keeps every event."""

    def __init__(self, streams: dict[str, str], name: str = 'NavTest') -> None:
        self.manager = CommsManager(name)
        self.manager.set_no_sleep()
        self.objects: dict[str, Any] = {}
        for stream, interface in streams.items():
            obj = robot_object_class(interface)(stream)
            obj.set_queue_mode(True)
            self.manager.register_consumer(obj)
            self.objects[stream] = obj
        self.events: dict[str, list[Any]] = {s: [] for s in streams}

    def pump(self) -> None:
        self.manager.step()
        for stream, obj in self.objects.items():
            while obj.get_next_data():
                self.events[stream].append(obj.data.ros_message())

    def until(self, predicate: Callable[[], bool], what: str, timeout: float = 60.0,
              every: Callable[[], None] | None = None) -> None:
        deadline = time.monotonic() + timeout
        while True:
            self.pump()
            if predicate():
                return
            if time.monotonic() > deadline:
                counts = {s: len(e) for s, e in self.events.items()}
                raise AssertionError(f'{what}: not within {timeout} s; events so far: {counts}')
            if every is not None:
                every()
            self.manager.wait(0.05)

    def close(self) -> None:
        self.manager.clean_up()


def seconds(message: Any) -> float:
    return message.header.stamp.sec + message.header.stamp.nanosec * 1e-9


def interpolate_truth(truth: Sequence[Any], t: float) -> tuple[float, float, float] | None:
    """The true pose at ``t`` from Egomotion messages of the base's truth (None if not covered)."""
    for a, b in zip(truth, truth[1:]):
        ta, tb = seconds(a), seconds(b)
        if ta <= t <= tb:
            f = (t - ta) / (tb - ta) if tb > ta else 0.0
            la, lb = a.location, b.location
            turn = math.atan2(math.sin(lb.theta - la.theta), math.cos(lb.theta - la.theta))
            return la.x + f * (lb.x - la.x), la.y + f * (lb.y - la.y), la.theta + f * turn
    return None


def angle_error(a: float, b: float) -> float:
    return abs(math.atan2(math.sin(a - b), math.cos(a - b)))
