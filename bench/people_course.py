"""People who cross the robot's way, and how near the robot came to them: for bench/nav_people.py.

:func:`crossing_people` puts each person on the robot's planned way between two of its goals,
walking back and forth across it (perpendicular to the way, up to 2.5 m each side, as far as the
walls allow) at 0.5 m/s up to the benchmark's top speed: so people meet the robot head-on, from
the side and from behind, depending on when the robot comes.  Every walk is checked by the
simulator's own rules (:func:`wurde_drivers.sim.loading.load_sim`: into no wall, not over the
start) before it is kept.  :class:`Clearance` measures, at each truth sample, the gap between the
robot's disc and the nearest person's body, at the sample's own stamp (people's positions are a
pure function of the stamp, :mod:`wurde_drivers.sim.walk`).
"""

from __future__ import annotations

import collections
import dataclasses
import math
import pathlib
import random
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

if TYPE_CHECKING:
    from wurde_drivers.sim.people import People

#: m: how far either side of the way a crossing reaches at most, and at least in all.
REACH_M, SHORTEST_CROSSING_M = 2.5, 1.2
#: m: a person's crossing keeps this far from the goals and the start (it crosses between them).
AWAY_FROM_ENDS_M = 1.5


def _legs(map_file: pathlib.Path, start: tuple[float, float], goals: list[tuple[float, float]]):
    """The planned ways (polylines) from the start through the goals."""
    from pluto_motion.grid_planner import Planner
    from pluto_motion.planning_grid import grid_from_map_file
    planner = Planner(grid_from_map_file(map_file))
    here, legs = start, []
    for goal in goals:
        plan = planner.plan(here, goal)
        if plan.reachable:
            legs.append([here, *plan.waypoints])
        here = goal
    return legs


def _point_along(leg: list[tuple[float, float]], rng: random.Random) -> tuple[tuple[float, float], float] | None:
    """A point of ``leg`` at least :data:`AWAY_FROM_ENDS_M` from both ends, and the heading there."""
    lengths = [math.dist(a, b) for a, b in zip(leg, leg[1:])]
    total = sum(lengths)
    if total < 2 * AWAY_FROM_ENDS_M + 0.5:
        return None
    s = rng.uniform(AWAY_FROM_ENDS_M, total - AWAY_FROM_ENDS_M)
    for (a, b), length in zip(zip(leg, leg[1:]), lengths):
        if s <= length and length > 0:
            f = s / length
            return (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])), math.atan2(b[1] - a[1], b[0] - a[0])
        s -= length
    return None


def _extent(world, point, direction: float, margin: float) -> float:
    """How far from ``point`` along ``direction`` a body keeps ``margin`` from every wall."""
    step, reach = 0.05, 0.0
    while reach + step <= REACH_M:
        q = (point[0] + (reach + step) * math.cos(direction), point[1] + (reach + step) * math.sin(direction))
        if world.distance_to_nearest_wall(q) < margin:
            break
        reach += step
    return reach


def crossing_people(sim_config: pathlib.Path, map_file: pathlib.Path, goals: list[tuple[float, float]],
                    count: int, seed: int, top_speed: float) -> list[dict[str, str]]:
    """``count`` people's ``<person>`` attributes crossing the way through ``goals``; each one's
    walk is accepted by the simulator with the people kept before it.  Fewer when the map has no
    room for more (each try that the simulator refuses is dropped)."""
    from wurde_drivers.sim.loading import load_sim
    from wurde_drivers.sim.mapfile import load_map
    from wurde_idl.errors import ConfigError

    world = load_map(str(map_file))
    _, _, start = load_sim(str(sim_config))
    legs = _legs(map_file, start[:2], goals)
    rng = random.Random(seed)
    kept: list[dict[str, str]] = []
    for _ in range(200):
        if len(kept) == count or not legs:
            break
        found = _point_along(rng.choice(legs), rng)
        if found is None:
            continue
        (x, y), heading = found
        if math.dist((x, y), start[:2]) < AWAY_FROM_ENDS_M:
            continue
        box = rng.random() < 0.25
        reach = math.hypot(0.45, 0.3) if box else 0.25
        across = heading + math.pi / 2
        left, right = (_extent(world, (x, y), across + side, reach + 0.1) for side in (0.0, math.pi))
        if left + right < SHORTEST_CROSSING_M:
            continue
        a = (x + left * math.cos(across), y + left * math.sin(across))
        b = (x - right * math.cos(across), y - right * math.sin(across))
        person = {'name': f'p{len(kept)}', 'points': f'{a[0]:.2f},{a[1]:.2f} {b[0]:.2f},{b[1]:.2f}',
                  'speed': f'{rng.uniform(0.5, top_speed):.2f}', 'pause': f'{rng.uniform(0.0, 2.0):.1f}',
                  'mode': 'back-and-forth', 'height': '1.7',
                  **({'length': '0.9', 'width': '0.6'} if box else {'radius': '0.25'})}
        trial = sim_config.with_name('sim-config.trial.xml')
        write_people(sim_config, [*kept, person], trial)
        try:
            load_sim(str(trial))
        except ConfigError:
            continue
        finally:
            trial.unlink(missing_ok=True)
        kept.append(person)
    return kept


def write_people(sim_config: pathlib.Path, people: list[dict[str, str]], out: pathlib.Path | None = None) -> None:
    """``sim_config`` with ``people`` as its ``<person>`` elements (replacing any), to ``out``
    (default: in place)."""
    tree = etree.parse(str(sim_config))
    root = tree.getroot()
    for node in root.findall('person'):
        root.remove(node)
    for person in people:
        etree.SubElement(root, 'person', **person)
    tree.write(str(out or sim_config))


#: m/s: slower is standing (the truth's and the walk's jitter)
STANDING = 0.05


@dataclasses.dataclass
class Clearance:
    """The gap between the robot's disc and the nearest person, over the truth samples given, and
    each contact's kind (:meth:`kind`)."""

    people: People
    radius: float
    least: float = math.inf
    contacts: int = 0
    kinds: collections.Counter = dataclasses.field(default_factory=collections.Counter)
    _touching: bool = False
    _last: tuple[float, float, float] | None = None

    def add(self, stamp: float, x: float, y: float) -> None:
        if not len(self.people):
            return
        ids, gaps, _ = self.people.shapes_at(stamp).nearest((x, y))
        gap = float(gaps.min()) - self.radius
        self.least = min(self.least, gap)
        touching = gap <= 0.0
        if touching and not self._touching:                    # a contact is each new touch
            self.contacts += 1
            self.kinds[self.kind(stamp, x, y, int(ids[int(np.argmin(gaps))]))] += 1
        self._touching = touching
        self._last = (stamp, x, y)

    def kind(self, stamp: float, x: float, y: float, who: int) -> str:
        """Who moved at a contact: the robot into a person standing, a person into the robot
        standing, both; and whether the person had set off within the last second."""
        robot = 0.0
        if self._last is not None and stamp > self._last[0]:
            robot = math.dist((x, y), self._last[1:]) / (stamp - self._last[0])

        def speed(at: float) -> float:
            return math.dist(self.people.poses_at(at)[who][:2], self.people.poses_at(at - 0.2)[who][:2]) / 0.2

        person = speed(stamp)
        if person < STANDING:
            return 'robot into a person standing'
        who_moved = 'person into the robot standing' if robot < STANDING else 'both moving'
        set_off = min(speed(stamp - 0.2 * k) for k in range(1, 6)) < STANDING
        return f'{who_moved}, {"set off within 1 s" if set_off else "walking for 1 s or more"}'
