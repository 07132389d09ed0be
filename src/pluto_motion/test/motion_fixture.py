"""Helpers for the motionModule tests: the whole simulated Pluto of config/pluto (dummies with its
odometry and laser noise, localModule, poseModule) and the chain drive -> avoid -> motion as real
processes on a given map, and a test-side module with a MotionProxy that records every status and
the simulator's truth."""

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
from wurde_core.interfaces import Egomotion
from wurde_drivers.sim.mapfile import load_map
from wurde_testing import ChildProcess, find_executable

from pluto_motion.motion_proxy import MotionProxy

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'
RADIUS = 0.35


def pluto_config(directory: pathlib.Path, map_file: pathlib.Path) -> pathlib.Path:
    """config/pluto's sim-config (its noise) with ``map_file`` as map.xml, in ``directory``."""
    (directory / 'map.xml').write_bytes(map_file.read_bytes())
    tree = etree.parse(str(PLUTO / 'sim-config.xml'))
    tree.write(str(directory / 'sim-config.xml'))
    return directory


def program(package: str, name: str, directory: pathlib.Path, *args: str) -> ChildProcess:
    """The executable ``package``/``name`` with ``args``, its config and logs in ``directory``."""
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory))
    return ChildProcess([find_executable(package, name), *args], env=env)


@contextlib.contextmanager
def pluto(directory: pathlib.Path, *motion_args: str) -> Iterator[dict[str, ChildProcess]]:
    """Dummies, localization and the movement chain, stopped at the end (in reverse order)."""
    specs = [('base', 'wurde_drivers', 'dummy_base', ('-n', 'PlutoBase')),
             ('laser', 'wurde_drivers', 'dummy_sick', ('-n', 'PlutoLaser')),
             ('local', 'pluto_nav', 'local_module', ('-n', 'localModule', '-m', 'map.xml')),
             ('pose', 'pluto_nav', 'pose_module', ('-n', 'poseModule', '-m', 'map.xml')),
             ('drive', 'pluto_motion', 'drive_module', ()),
             ('avoid', 'pluto_motion', 'avoid_module', ()),
             ('motion', 'pluto_motion', 'motion_module', motion_args)]
    with contextlib.ExitStack() as stack:
        yield {name: stack.enter_context(program(package, exe, directory, *args))
               for name, package, exe, args in specs}


class Commander:
    """The test's module: a MotionProxy, every motion status and the truth."""

    def __init__(self, map_file: pathlib.Path) -> None:
        self.manager = CommsManager('MotionTest')
        self.manager.set_no_sleep()
        self.motion = MotionProxy(self.manager, queue_mode=True)
        self.truth = Egomotion('PlutoBaseTruth')
        self.truth.set_queue_mode(True)
        self.manager.register_consumer(self.truth)
        self.world = load_map(map_file)
        self.truths: list[tuple[float, float, float]] = []
        self.speeds: list[float] = []           # the truth's tv, with each of ``truths``
        self.statuses: list[Any] = []
        self.children: dict[str, ChildProcess] = {}

    def pump(self) -> None:
        self.manager.step()
        self.statuses.extend(self.motion.update())
        while self.truth.get_next_data():
            loc = self.truth.data.location
            self.truths.append((loc.x(), loc.y(), loc.theta()))
            self.speeds.append(float(self.truth.data.tv))

    def until(self, predicate: Callable[[], bool], what: str, timeout: float = 60.0,
              every: Callable[[], object] | None = None, period: float = 1.0) -> None:
        """Pump until ``predicate()``, then once more (a predicate that polls a task takes statuses
        in that only the next pump reports); ``every`` is called at most each ``period`` s."""
        deadline = time.monotonic() + timeout
        sent = -math.inf
        while not predicate():
            self.pump()
            for name, child in self.children.items():
                if child.process.poll() is not None:
                    raise AssertionError(f'{what}: {name} exited ({child.process.returncode}): {child.stderr}')
            now = time.monotonic()
            if now > deadline:
                raise AssertionError(f'{what}: not within {timeout} s; status {self.motion.data} '
                                     f'{self.motion.element}, truth {self.truths[-1] if self.truths else None}')
            if every is not None and now - sent >= period:
                every()
                sent = now
            self.manager.wait(0.05)
        self.pump()

    def closest_to_walls(self, since: int = 0) -> float:
        """The smallest distance (m) of the truth from any wall since truth sample ``since``."""
        return min((self.world.distance_to_nearest_wall(p[:2]) for p in self.truths[since:]), default=math.inf)

    def close(self) -> None:
        self.manager.clean_up()
