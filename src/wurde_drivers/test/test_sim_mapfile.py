"""Map files: the shipped maps load and make sense, round trips are exact, bad maps are refused
with file and line."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest

from wurde_drivers.errors import ConfigError, MapError
from wurde_drivers.sim.mapfile import load_map, save_map
from wurde_drivers.sim.world import World

MAPS = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'
SHIPPED = ['office', 'corridor-loop', 'outdoor']


@pytest.mark.parametrize('name', SHIPPED)
def test_each_shipped_map_loads_with_a_free_start(name: str) -> None:
    world = load_map(MAPS / f'{name}.xml')
    assert world.name == name
    assert len(world.walls) >= 10
    start = world.place('start')
    assert world.is_free(start[:2], clearance=1.0)
    for place_name, place in world.places.items():
        assert world.is_free(place[:2], clearance=0.5), place_name


def test_the_office_has_rooms_with_doors_off_a_corridor() -> None:
    world = load_map(MAPS / 'office.xml')
    assert {'start', 'kitchen', 'lab', 'office1', 'office2'} <= set(world.places)
    xmin, ymin, xmax, ymax = world.bounds
    assert (xmax - xmin, ymax - ymin) == (20, 15)
    start = world.place('start')
    for room in ('office1', 'office2', 'lab', 'kitchen', 'office3', 'conference', 'office4'):
        place = world.place(room)
        door_x = {'office1': 2.5, 'office2': 7.5, 'lab': 12.5, 'kitchen': 17.5, 'office3': 3.5,
                  'conference': 10.0, 'office4': 16.5}[room]
        # Corridor -> door -> room is free for a robot of radius 0.3; a metre aside is a wall.
        corridor = (door_x, start.y)
        assert world.first_contact(corridor, (door_x, place.y), 0.3) == 1.0, room
        assert world.segment_blocked((door_x + 1.0, start.y), (door_x + 1.0, place.y)), room
    assert world.offlimits


def test_the_corridor_loop_goes_all_the_way_round() -> None:
    world = load_map(MAPS / 'corridor-loop.xml')
    corners = ['start', 'corner_nw', 'mid_north', 'corner_ne', 'mid_east', 'corner_se',
               'mid_south', 'corner_sw', 'start']
    for a, b in zip(corners, corners[1:]):
        assert world.first_contact(world.place(a)[:2], world.place(b)[:2], 0.3) == 1.0, (a, b)
    # The block in the middle: no way straight across.
    assert world.segment_blocked(world.place('start')[:2], world.place('mid_east')[:2])


def test_the_outdoor_map_has_buildings_and_off_limits() -> None:
    world = load_map(MAPS / 'outdoor.xml')
    assert tuple(world.bounds) == (0, 0, 80, 60)
    assert len(world.offlimits) >= 1 and len(world.walls) >= 20
    scan = world.raycast(world.place('start')[:2], np.linspace(-math.pi, math.pi, 361), 30.0)
    assert np.any(scan == 30.0) and np.any(scan < 30.0)  # open ground and a fence


@pytest.mark.parametrize('name', SHIPPED)
def test_round_trip_of_a_shipped_map_is_exact(name: str, tmp_path: pathlib.Path) -> None:
    world = load_map(MAPS / f'{name}.xml')
    save_map(world, tmp_path / 'copy.xml')
    again = load_map(tmp_path / 'copy.xml')
    assert again == world
    assert again.places == world.places and list(again.places) == list(world.places)


def test_round_trip_keeps_awkward_floats_exactly(tmp_path: pathlib.Path) -> None:
    walls = [(0.1 + 0.2, 1e-17, 1 / 3, -0.0), (math.pi, math.e, 12345.678901234567, 2 ** -30)]
    world = World(walls, places={'a': (0.1, 0.7, -math.pi), 'b.2-x_y': (1 / 7, 2 / 7, 3 / 7)},
                  offlimits=[[(0.1, 0.1), (0.3, 0.1), (0.2, 0.2 + 1e-12)]],
                  bounds=(-1.5, -2.25, 12346, 4), name='awkward')
    save_map(world, tmp_path / 'awkward.xml')
    again = load_map(tmp_path / 'awkward.xml')
    assert again == world
    assert again.walls.tobytes() == world.walls.tobytes()


def write(tmp_path: pathlib.Path, body: str, *, header: str = '') -> pathlib.Path:
    path = tmp_path / 'bad.xml'
    path.write_text(f'<?xml version="1.0"?>\n{header}<map name="bad" version="1.0">\n'
                    f'{body}</map>\n')
    return path


BAD = [
    ('unknown tag', '  <door x="1"/>\n', 3, 'unknown element <door>'),
    ('unknown attribute', '  <wall x1="0" y1="0" x2="1" y2="0" z="3"/>\n', 3, 'unknown attribute'),
    ('missing attribute', '  <wall x1="0" y1="0" x2="1"/>\n', 3, 'y2'),
    ('not a number', '  <place name="a" x="1m" y="0"/>\n', 3, 'x="1m"'),
    ('not finite', '  <place name="a" x="nan" y="0"/>\n', 3, 'not finite'),
    ('infinite wall', '  <wall x1="0" y1="0" x2="inf" y2="0"/>\n', 3, 'not finite'),
    ('zero-length wall', '  <wall x1="1" y1="2" x2="1" y2="2"/>\n', 3, 'zero length'),
    ('duplicate place', '  <place name="a" x="1" y="0"/>\n\n  <place name="a" x="2" y="0"/>\n',
     5, 'duplicate place "a" (first on line 3)'),
    ('polygon with 2 points', '  <offlimits points="0,0 1,1"/>\n', 3, 'at least 3 points'),
    ('flat polygon', '  <offlimits points="0,0 1,1 2,2"/>\n', 3, 'zero area'),
    ('polyline of 1 point', '  <polyline points="0,0"/>\n', 3, 'at least 2 points'),
    ('closed polyline of 2', '  <polyline points="0,0 1,0" closed="true"/>\n', 3, 'at least 3'),
    ('repeated point', '  <polyline points="0,0 1,0 1,0 1,1"/>\n', 3, 'zero-length'),
    ('closing point repeated', '  <polyline points="0,0 1,0 1,1 0,0" closed="true"/>\n', 3,
     'already joins'),
    ('bad pair', '  <polyline points="0,0 1;0"/>\n', 3, '"1;0" is not x,y'),
    ('bad boolean', '  <polyline points="0,0 1,0" closed="maybe"/>\n', 3, 'true or false'),
    ('bad place name', '  <place name="my place" x="1" y="0"/>\n', 3, 'letters, digits'),
    ('second bounds', '  <bounds xmin="0" ymin="0" xmax="1" ymax="1"/>\n'
     '  <bounds xmin="0" ymin="0" xmax="2" ymax="2"/>\n', 4, 'second <bounds>'),
    ('empty bounds', '  <bounds xmin="0" ymin="0" xmax="0" ymax="1"/>\n', 3, 'xmin < xmax'),
    ('place outside bounds', '  <bounds xmin="0" ymin="0" xmax="5" ymax="5"/>\n'
     '  <place name="far" x="9" y="1"/>\n', 4, 'outside the <bounds> of line 3'),
    ('wall outside bounds', '  <wall x1="0" y1="0" x2="9" y2="0"/>\n'
     '  <bounds xmin="0" ymin="0" xmax="5" ymax="5"/>\n', 3, 'leaves the <bounds> of line 4'),
    ('malformed XML', '  <wall x1="0" y1="0" x2="1" y2="0">\n', 4, 'not well-formed'),
]


@pytest.mark.parametrize('body, line, reason', [case[1:] for case in BAD],
                         ids=[case[0] for case in BAD])
def test_bad_maps_are_refused_with_file_and_line(tmp_path: pathlib.Path, body: str, line: int,
                                                 reason: str) -> None:
    path = write(tmp_path, body)
    with pytest.raises(MapError) as caught:
        load_map(path)
    error = caught.value
    assert (error.path, error.line) == (str(path), line)
    assert reason in error.reason
    assert str(error).startswith(f'{path}:{line}: ')
    assert isinstance(error, ConfigError)


def test_a_doctype_with_an_internal_subset_is_refused(tmp_path: pathlib.Path) -> None:
    header = '<!DOCTYPE map [\n  <!ENTITY boom "boom">\n]>\n'
    path = write(tmp_path, '  <place name="&boom;" x="1" y="1"/>\n', header=header)
    with pytest.raises(MapError) as caught:
        load_map(path)
    assert (caught.value.path, caught.value.line) == (str(path), 2)
    assert 'internal subset' in caught.value.reason


def test_wrong_root_version_and_missing_file_are_refused(tmp_path: pathlib.Path) -> None:
    other = tmp_path / 'other.xml'
    other.write_text('<?xml version="1.0"?>\n<world name="x" version="1.0"/>\n')
    with pytest.raises(MapError, match=r'other\.xml:2: root element is <world>'):
        load_map(other)
    version = tmp_path / 'version.xml'
    version.write_text('<?xml version="1.0"?>\n\n<map name="x" version="2.0"/>\n')
    with pytest.raises(MapError, match=r'version\.xml:3: .*version="2.0"'):
        load_map(version)
    with pytest.raises(MapError, match='cannot read'):
        load_map(tmp_path / 'missing.xml')


def test_the_examples_of_the_readme_and_the_docstring_load(tmp_path: pathlib.Path) -> None:
    from wurde_drivers.sim import mapfile

    readme = (MAPS / 'README.md').read_text()
    snippet = readme.split('```xml\n', 1)[1].split('```', 1)[0]
    docstring = mapfile.__doc__.split('::\n', 1)[1].split('\nElements', 1)[0]
    for index, text in enumerate((snippet, docstring)):
        path = tmp_path / f'example{index}.xml'
        path.write_text(text.strip() + '\n')
        world = load_map(path)
        assert world.name == 'office' and world.place('start') == (3, 7.5, 0)
        assert world.is_off_limits((14, 3.5)) == (index == 0)


def test_a_map_without_bounds_gets_the_box_around_its_contents(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path, '  <wall x1="-1" y1="2" x2="3" y2="2"/>\n'
                           '  <place name="p" x="0" y="-4"/>\n'
                           '  <offlimits points="0,0 5,0 5,1"/>\n')
    world = load_map(path)
    assert tuple(world.bounds) == (-1, -4, 5, 2)
    assert world.place('p').theta == 0.0


def test_the_simulator_runs_in_a_carmen_map_its_walls_where_the_grid_is(tmp_path: pathlib.Path) -> None:
    """A CARMEN map (the outlines of its occupied cells as walls): a laser in the middle of a
    4 m x 3 m room measures its walls within a cell, and the map's places come with it."""
    from wurde_testing.carmen_maps import carmen_map_bytes
    probability = np.zeros((80, 60))                       # [x, y] at 0.05 m
    probability[:, [0, -1]] = probability[[0, -1], :] = 1.0
    path = tmp_path / 'room.map'
    path.write_bytes(carmen_map_bytes(probability, 0.05, places=[(1, 'start', (2.0, 1.5, 0.0))]))
    world = load_map(path)
    assert world.place('start') == (2.0, 1.5, 0.0)
    ranges = world.raycast((2.0, 1.5), np.array([0.0, math.pi / 2, math.pi, -math.pi / 2]))
    # The inner faces of the one-cell walls: 1.95 m and 1.45 m from the centre, to within a cell.
    assert ranges == pytest.approx([1.95, 1.45, 1.95, 1.45], abs=0.05)
