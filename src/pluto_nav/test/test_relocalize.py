"""The poseModule's line filter re-localizes against the map when its pose stops fitting the
scans (pluto_nav.relocalize, issue 38).  Started sure of a heading 25 degrees off (a soak's base
restart left one 14 degrees off, and the filter held it 27 s; alone it holds 25 degrees on every
office route tried), it is back within 0.1 m and 2 degrees of the truth within a few scans, on a
shipped map and generated ones, with noise on.  Started right, it never jumps, also among boxes
that are not in the map."""

from __future__ import annotations

import math

import numpy as np
import pytest
import random_maps
import slam_sim
from wurde_drivers.sim.laser import LaserGeometry
from wurde_drivers.sim.mapfile import load_map
from wurde_drivers.sim.world import World

from pluto_nav.estimation import Scan, ScanCycle
from pluto_nav.geometry import compose, wrap
from pluto_nav.localizers import LineLocalizer
from pluto_nav.relocalize import STRIKES
from pluto_nav.wall_map import WallMap

MAPS = slam_sim.__file__.rsplit('/src/', 1)[0] + '/config/maps'
ANGLES = np.linspace(-math.pi / 2, math.pi / 2, 361)
#: Sure of a pose that is off: 25 degrees and 10 cm, held with 2 cm and 0.5 degree.
OFF = (0.1, 0.0, math.radians(25.0))
SURE = np.diag([0.02, 0.02, math.radians(0.5)]) ** 2
#: Scans within which the pose must be back: the strikes, then the search's own scan and a few more.
SCANS = STRIKES + 7


def _run(world: World, map_walls: np.ndarray, seed: int, off: tuple[float, float, float], *,
         relocalize: bool = True, length: float = 12.0) -> tuple[np.ndarray, LineLocalizer]:
    """Position and heading errors per scan of a LineLocalizer started ``off`` the truth."""
    found = []
    localizer = LineLocalizer(WallMap(map_walls), relocalize=relocalize, on_relocalize=found.append)
    cycle = ScanCycle(localizer)
    errors = []
    route = slam_sim.loop_route(world, length, np.random.default_rng(seed))
    for k, scan in enumerate(slam_sim.drive(world, route, seed=seed)):
        start = (compose(scan.truth, off), SURE)
        cycle.step(Scan(float(k), scan.ranges, ANGLES, LaserGeometry().max_range), scan.dead_reckoning,
                   scan.increment_covariance, start=start)
        pose = cycle.method.pose
        errors.append((math.dist(pose[:2], scan.truth[:2]), abs(float(wrap(pose[2] - scan.truth[2])))))
    assert len(found) == (0 if localizer.relocalizer is None else len(localizer.relocalizer.found))
    return np.array(errors), localizer


@pytest.mark.parametrize('name', ['office', 'random 3', 'random 11'])
def test_a_filter_sure_of_a_wrong_heading_is_re_localized_within_a_few_scans(name: str) -> None:
    world = load_map(f'{MAPS}/office.xml') if name == 'office' else random_maps.random_map(int(name.split()[1]))
    errors, localizer = _run(world, world.walls, 5, OFF)
    assert localizer.relocalizer is not None and localizer.relocalizer.found
    after = errors[SCANS:]
    assert after[:, 0].max() < 0.1 and np.degrees(after[:, 1].max()) < 2.0, errors[:SCANS + 5]
    if name == 'office':
        # The filter alone holds the error (what the soak saw); on the generated maps tried its
        # own recovery (lines matched again in wider gates) finds the way too.
        alone, _ = _run(world, world.walls, 5, OFF, relocalize=False)
        assert np.degrees(alone[SCANS:SCANS + 10, 1].min()) > 5.0


@pytest.mark.parametrize('seed', [1, 2])
def test_started_right_it_never_jumps_even_among_boxes_not_in_the_map(seed: int) -> None:
    world = load_map(f'{MAPS}/office.xml')
    rng = np.random.default_rng(seed)
    boxes = []
    lo, hi = world.walls.reshape(-1, 2).min(axis=0) + 1.0, world.walls.reshape(-1, 2).max(axis=0) - 1.0
    for x, y in rng.uniform(lo, hi, size=(25, 2)):      # 0.3 m boxes: furniture the map lacks
        corners = [(x, y), (x + 0.3, y), (x + 0.3, y + 0.3), (x, y + 0.3)]
        boxes += [(*a, *b) for a, b in zip(corners, corners[1:] + corners[:1])]
    cluttered = World(np.vstack([world.walls, np.array(boxes)]), places=world.places)
    errors, localizer = _run(cluttered, world.walls, seed, (0.0, 0.0, 0.0), length=15.0)
    assert localizer.relocalizer is not None and not localizer.relocalizer.found
    assert errors[:, 0].max() < 0.1 and np.degrees(errors[:, 1].max()) < 2.0
