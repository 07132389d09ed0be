"""Random maps and routes (wurde_drivers.sim.generate): maps that save and load equal, a free
start, connected places, walls at varied angles; routes whose legs keep their clearance, reach
their length and cover the map; the same seed gives the same map; the command line."""

from __future__ import annotations

import math
import os
import pathlib
import re
import subprocess
import sys
import tempfile

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.sim.generate import KINDS, format_route, main, random_map
from wurde_drivers.sim.loading import load_sim
from wurde_drivers.sim.mapfile import load_map, save_map
from wurde_drivers.sim.route import CLEARANCE, Roadmap, random_route, route_length
from wurde_drivers.sim.tour import _route as tour_waypoints
from wurde_drivers.sim.world import World

#: Small maps keep each example well under a second; hypothesis examples are derandomised so a
#: run is repeatable.
FAST = settings(max_examples=12, deadline=None, derandomize=True)
seeds = st.integers(min_value=0, max_value=2 ** 31)
kinds = st.sampled_from(KINDS)
sizes = st.floats(min_value=10.0, max_value=25.0)


def offlimits_edges(world: World) -> World | None:
    """The off-limits polygons' edges as walls, to sweep the robot's disc against them."""
    edges = [np.hstack([polygon, np.roll(polygon, -1, axis=0)]) for polygon in world.offlimits]
    return World(np.vstack(edges)) if edges else None


def assert_route_clear(world: World, route: list[tuple[float, float]], clearance: float) -> None:
    regions = offlimits_edges(world)
    for a, b in zip(route, route[1:]):
        assert a != b
        assert world.first_contact(a, b, clearance) == 1.0, (a, b)
        assert regions is None or regions.first_contact(a, b, clearance) == 1.0, (a, b)
        assert not world.is_off_limits(b) and world.bounds.contains(*b), b


@FAST
@given(seed=seeds, kind=kinds, size=sizes)
def test_a_map_is_its_seed_saves_and_loads_equal_and_starts_free(seed: int, kind: str,
                                                                  size: float) -> None:
    world = random_map(seed, kind, size=size)
    assert world == random_map(seed, kind, size=size)
    assert world.name == f'{kind}-{seed}'
    with tempfile.TemporaryDirectory() as directory:
        path = pathlib.Path(directory) / 'map.xml'
        save_map(world, path)
        assert load_map(path) == world
    start = world.place('start')
    assert world.is_free(start[:2], clearance=1.0)
    for name, place in world.places.items():
        assert world.is_free(place[:2], clearance=0.5), name
    width, height = world.bounds.xmax - world.bounds.xmin, world.bounds.ymax - world.bounds.ymin
    assert 0.7 * size <= max(width, height) <= 1.5 * size


@FAST
@given(seed=seeds, kind=kinds, size=sizes)
def test_every_place_is_reachable_from_start(seed: int, kind: str, size: float) -> None:
    world = random_map(seed, kind, size=size)
    roadmap = Roadmap(world, CLEARANCE, seed=seed)
    start = roadmap.add(world.place('start')[:2])
    places = {name: roadmap.add(place[:2]) for name, place in world.places.items()}
    reachable = set(roadmap.reachable(start).tolist())
    assert {name for name, node in places.items() if node not in reachable} == set()
    assert len(places) >= 2


@settings(max_examples=6, deadline=None, derandomize=True)
@given(seed=seeds, size=sizes)
def test_rooms_doors_are_at_least_0_9_m_wide(seed: int, size: float) -> None:
    """A disc of radius 0.445 m reaches every room: no door (and no gap) is narrower than 0.89."""
    world = random_map(seed, 'rooms', size=size)
    roadmap = Roadmap(world, 0.445, seed=seed)
    start = roadmap.add(world.place('start')[:2])
    rooms = {name: roadmap.add(place[:2]) for name, place in world.places.items()
             if name.startswith('room')}
    reachable = set(roadmap.reachable(start).tolist())
    assert rooms and {name for name, node in rooms.items() if node not in reachable} == set()


@pytest.mark.parametrize('kind', KINDS)
def test_walls_run_at_varied_angles(kind: str) -> None:
    for seed in range(4):
        walls = random_map(seed, kind, size=20.0).walls
        angles = np.mod(np.arctan2(walls[:, 3] - walls[:, 1], walls[:, 2] - walls[:, 0]), math.pi)
        directions = np.unique(np.round(angles, 3) % round(math.pi, 3))
        assert len(directions) >= 3, (kind, seed)
        quarter = np.mod(angles, math.pi / 2)
        off_axis = np.minimum(quarter, math.pi / 2 - quarter)
        assert np.any(off_axis > 0.05), (kind, seed)


def test_different_seeds_and_kinds_give_different_maps() -> None:
    maps = [random_map(seed, kind, size=15.0) for kind in KINDS for seed in (1, 2)]
    assert all(a != b for i, a in enumerate(maps) for b in maps[i + 1:])


@FAST
@given(seed=seeds, kind=kinds, size=sizes, length=st.floats(min_value=5.0, max_value=120.0))
def test_route_legs_keep_their_clearance_and_reach_the_length(seed: int, kind: str, size: float,
                                                               length: float) -> None:
    world = random_map(seed, kind, size=size)
    route = random_route(world, seed, length)
    assert route[0] == tuple(world.place('start')[:2])
    assert route_length(route) >= length
    assert_route_clear(world, route, CLEARANCE)
    assert route == random_route(world, seed, length)


@FAST
@given(seed=seeds, kind=kinds, size=sizes, length=st.floats(min_value=5.0, max_value=60.0))
def test_a_route_home_is_a_clear_loop_back_to_start(seed: int, kind: str, size: float, length: float) -> None:
    world = random_map(seed, kind, size=size)
    out = random_route(world, seed, length)
    loop = random_route(world, seed, length, home=True)
    assert loop[:len(out)] == out
    assert loop[-1] == tuple(world.place('start')[:2])
    assert out[-1] == loop[-1] or len(loop) > len(out)
    assert_route_clear(world, loop, CLEARANCE)


def test_a_wider_robot_gets_a_route_with_more_room() -> None:
    world = random_map(3, 'outdoor', size=30.0)
    route = random_route(world, 3, 80.0, clearance=0.8)
    assert route_length(route) >= 80.0
    assert_route_clear(world, route, 0.8)


@pytest.mark.parametrize('kind', KINDS)
def test_a_long_route_covers_the_map(kind: str) -> None:
    """Four times the perimeter of the map's box passes within 2 m of every place."""
    for seed in (0, 1):
        world = random_map(seed, kind, size=20.0)
        box = world.bounds
        route = random_route(world, seed, 8 * ((box.xmax - box.xmin) + (box.ymax - box.ymin)))
        points = np.array(route)
        for name, place in world.places.items():
            nearest = min(_point_to_leg(place[:2], a, b) for a, b in zip(points, points[1:]))
            assert nearest <= 2.0, (kind, seed, name)


def _point_to_leg(point: tuple[float, float], a: np.ndarray, b: np.ndarray) -> float:
    t = np.clip(np.dot(np.subtract(point, a), b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.hypot(*(a + t * (b - a) - point)))


def test_the_shipped_maps_get_routes_too() -> None:
    maps = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'
    for name in ('office', 'corridor-loop'):
        world = load_map(maps / f'{name}.xml')
        route = random_route(world, 1, 60.0)
        assert route_length(route) >= 60.0
        assert_route_clear(world, route, CLEARANCE)


def test_bad_requests_are_refused() -> None:
    with pytest.raises(ValueError, match='unknown kind'):
        random_map(1, 'castle')
    with pytest.raises(ValueError, match='size must be'):
        random_map(1, 'maze', size=5.0)
    def box(side: float) -> World:
        return World([(0, 0, side, 0), (side, 0, side, side), (side, side, 0, side),
                      (0, side, 0, 0)], places={'start': (side / 2, side / 2)})

    with pytest.raises(ValueError, match='not free'):
        random_route(box(0.7), 1, 10.0)
    with pytest.raises(ValueError, match='no clear leg leaves start'):
        random_route(box(1.0), 1, 10.0)
    with pytest.raises(KeyError, match='start'):
        random_route(World([(0, 0, 5, 0)]), 1, 10.0)
    assert random_route(random_map(1, 'maze', size=12.0), 1, 0.0) == [
        tuple(random_map(1, 'maze', size=12.0).place('start')[:2])]


def test_the_command_line_writes_the_map_and_prints_a_route_for_tour(
        tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / 'maze.xml'
    assert main(['--seed', '4', '--kind', 'maze', '--size', '15', '-o', str(path),
                 '--route-length', '40']) == 0
    world = load_map(path)
    assert world == random_map(4, 'maze', size=15.0)
    printed = capsys.readouterr().out.strip()
    expected = random_route(world, 4, 40.0)
    assert printed == format_route(expected[1:])
    assert tour_waypoints(printed) == expected[1:]
    assert main(['--seed', '4', '--kind', 'maze', '--size', '5', '-o', str(path)]) == 2
    assert 'size must be' in capsys.readouterr().err


@pytest.mark.process
def test_the_readme_example_writes_a_map_a_route_and_a_sim_config(tmp_path: pathlib.Path) -> None:
    root = pathlib.Path(__file__).resolve().parents[3]
    text = (root / 'config' / 'maps' / 'README.md').read_text()
    start = text.index('<!-- example: generate -->')
    block = re.compile(r'```bash\n(.*?)```', re.S).search(text, start).group(1)
    (tmp_path / 'config').symlink_to(root / 'config')
    env = dict(os.environ, PATH=f'{pathlib.Path(sys.executable).parent}:{os.environ["PATH"]}')
    result = subprocess.run(['bash', '-e', '-c', block], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    assert 'route of' in result.stderr
    world = random_map(7, 'maze', size=20.0)
    assert load_map(tmp_path / 'maze-7.xml') == world
    config, loaded, start_pose = load_sim(str(tmp_path / 'sim-config.xml'))
    assert loaded == world and start_pose[:2] == tuple(world.place('start')[:2])
    waypoints = tour_waypoints((tmp_path / 'route.txt').read_text())
    assert waypoints == random_route(world, 7, 100.0)[1:]
