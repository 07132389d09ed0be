"""Occupancy grids: rasterising a world, recovering its walls, ROS map_server files."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest

from wurde_drivers.errors import MapError
from wurde_drivers.sim.grid import OCCUPIED, UNKNOWN, OccupancyGrid, walls_from_grid
from wurde_drivers.sim.world import World

ROOM = [(0, 0, 4, 0), (4, 0, 4, 3), (4, 3, 0, 3), (0, 3, 0, 0)]
RESOLUTION = 0.1


def sample_walls(walls, step: float) -> np.ndarray:
    points = []
    for x1, y1, x2, y2 in np.asarray(walls, dtype=float):
        count = max(2, int(math.hypot(x2 - x1, y2 - y1) / step) + 1)
        t = np.linspace(0, 1, count)[:, None]
        points.append(np.array([x1, y1]) + t * np.array([x2 - x1, y2 - y1]))
    return np.vstack(points)


def test_grid_from_world_marks_exactly_the_cells_the_walls_cross() -> None:
    world = World(ROOM + [(0.5, 0.5, 3.3, 2.45)], bounds=(0, 0, 4, 3))
    grid = OccupancyGrid.from_world(world, RESOLUTION)
    assert grid.origin == (0.0, 0.0)
    assert (grid.width, grid.height) == (41, 31)
    assert set(np.unique(grid.data)) == {0.0, 1.0}
    ix, iy = grid.cells(sample_walls(world.walls, RESOLUTION / 20))
    assert np.all(grid.data[iy, ix] == OCCUPIED)  # every cell a wall passes through
    occupied_iy, occupied_ix = np.nonzero(grid.data == OCCUPIED)
    half_diagonal = RESOLUTION * math.sqrt(2) / 2
    for centre in grid.centers(occupied_ix, occupied_iy):  # and no cell it does not
        assert world.distance_to_nearest_wall(centre) <= half_diagonal + 1e-9
    assert grid.data[25, 10] == 0.0 and grid.data[5, 30] == 0.0  # free space stays free


def test_off_limits_are_marked_only_when_asked() -> None:
    world = World(ROOM, offlimits=[[(1, 1), (2, 1), (2, 2), (1, 2)]])
    plain = OccupancyGrid.from_world(world, RESOLUTION)
    planner = OccupancyGrid.from_world(world, RESOLUTION, offlimits=True)
    ix, iy = planner.cells([(1.5, 1.5)])
    assert plain.data[iy[0], ix[0]] == 0.0 and planner.data[iy[0], ix[0]] == OCCUPIED
    assert np.count_nonzero(planner.data) - np.count_nonzero(plain.data) == 100  # 10 x 10 cells


def test_walls_from_grid_reproduce_an_axis_aligned_room_within_one_cell() -> None:
    world = World(ROOM + [(2, 0, 2, 1.2)], bounds=(-1, -1, 5, 4))
    grid = OccupancyGrid.from_world(world, RESOLUTION)
    walls = walls_from_grid(grid)
    assert 5 <= len(walls) <= 10  # merged runs, not one segment per cell
    recovered = World(walls)
    for point in sample_walls(world.walls, 0.01):  # original -> recovered
        assert recovered.distance_to_nearest_wall(point) <= RESOLUTION
    for point in sample_walls(walls, 0.01):        # recovered -> original
        assert world.distance_to_nearest_wall(point) <= RESOLUTION
    angles = np.linspace(-math.pi, math.pi, 181)
    for origin in [(1, 1.5), (3, 2), (3.5, 0.5)]:
        # A laser in the recovered world sees walls within one cell of the original ones.
        ranges = recovered.raycast(origin, angles, 10)
        hits = np.asarray(origin) + ranges[:, None] * np.column_stack([np.cos(angles),
                                                                       np.sin(angles)])
        assert max(world.distance_to_nearest_wall(hit) for hit in hits) <= RESOLUTION


def test_walls_from_grid_handles_single_cells_and_oblique_walls() -> None:
    data = np.zeros((5, 5), dtype=np.float32)
    data[2, 2] = 1.0
    data[0, 4] = UNKNOWN  # unknown is not a wall
    grid = OccupancyGrid(data, 0.5, origin=(10, 20))
    np.testing.assert_allclose(walls_from_grid(grid), [[11.0, 21.25, 11.5, 21.25]])
    oblique = World([(0.05, 0.05, 2.95, 1.45)])
    stairs = World(walls_from_grid(OccupancyGrid.from_world(oblique, RESOLUTION)))
    for point in sample_walls(oblique.walls, 0.01):
        assert stairs.distance_to_nearest_wall(point) <= RESOLUTION * math.sqrt(2) / 2 + 1e-9
    assert len(walls_from_grid(OccupancyGrid(np.zeros((3, 3)), 1.0))) == 0


def test_to_world_covers_the_grid() -> None:
    grid = OccupancyGrid.from_world(World(ROOM), RESOLUTION)
    world = grid.to_world(name='from-grid')
    assert world.name == 'from-grid'
    assert world.bounds == pytest.approx((0, 0, 4.1, 3.1))
    assert world.distance_to_nearest_wall((2, 1.5)) == pytest.approx(1.45)


def test_pgm_yaml_round_trip_is_exact(tmp_path: pathlib.Path) -> None:
    grid = OccupancyGrid.from_world(World(ROOM + [(1, 1, 3, 2)]), RESOLUTION)
    grid.data[:3, :5] = UNKNOWN
    image = grid.save(tmp_path / 'room.yaml')
    assert image == tmp_path / 'room.pgm'
    assert image.read_bytes().startswith(b'P5')
    text = (tmp_path / 'room.yaml').read_text()
    assert 'image: room.pgm' in text and 'mode: trinary' in text
    assert 'origin: [0.0, 0.0, 0.0]' in text
    again = OccupancyGrid.load(tmp_path / 'room.yaml')
    assert again == grid
    assert again.data[0, 0] == UNKNOWN and again.data[0, 10] == OCCUPIED  # row 0 is lowest y


def test_other_map_server_modes_and_thresholds(tmp_path: pathlib.Path) -> None:
    import cv2

    pixels = np.array([[0, 100, 128], [200, 254, 255]], dtype=np.uint8)  # top row = highest y
    cv2.imwrite(str(tmp_path / 'm.pgm'), pixels)
    (tmp_path / 'scale.yaml').write_text('image: m.pgm\nresolution: 0.5\norigin: [1, 2, 0]\n'
                                         'mode: scale\noccupied_thresh: 0.65\nfree_thresh: 0.2\n')
    scale = OccupancyGrid.load(tmp_path / 'scale.yaml')
    assert scale.origin == (1.0, 2.0) and scale.resolution == 0.5
    assert scale.data[1, 0] == OCCUPIED and scale.data[0, 1] == 0.0
    assert scale.data[1, 2] == pytest.approx(((255 - 128) / 255 - 0.2) / 0.45, abs=1e-6)
    (tmp_path / 'raw.yaml').write_text('image: m.pgm\nresolution: 1\norigin: [0, 0, 0]\n'
                                       'mode: raw\n')
    raw = OccupancyGrid.load(tmp_path / 'raw.yaml')
    assert raw.data[1].tolist() == [0.0, 1.0, UNKNOWN] and raw.data[0, 2] == UNKNOWN


@pytest.mark.parametrize('text, line, reason', [
    ('resolution: 0.1\norigin: [0, 0, 0]\n', None, "missing key 'image'"),
    ('image: m.pgm\nresolution: fine\norigin: [0, 0, 0]\n', 2, 'finite number'),
    ('image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0.5]\n', 3, 'rotated'),
    ('image: m.pgm\nresolution: 0.1\norigin: [0, 0]\n', 3, '[x, y, yaw]'),
    ('image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nmode: fancy\n', 4, 'trinary'),
    ('image: nothing.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n', 1, 'cannot read'),
    ('image: m.pgm\nresolution: [0.1\n', 3, 'not valid YAML'),
    ('- a list\n', 1, 'mapping'),
])
def test_bad_map_yaml_is_refused_with_file_and_line(tmp_path: pathlib.Path, text: str,
                                                     line: int | None, reason: str) -> None:
    OccupancyGrid(np.zeros((2, 2)), 1.0).save(tmp_path / 'm.yaml')
    path = tmp_path / 'bad.yaml'
    path.write_text(text)
    with pytest.raises(MapError) as caught:
        OccupancyGrid.load(path)
    assert (caught.value.path, caught.value.line) == (str(path), line)
    assert reason in caught.value.reason


def test_grid_refuses_bad_construction() -> None:
    with pytest.raises(ValueError):
        OccupancyGrid(np.zeros(4), 0.1)
    with pytest.raises(ValueError):
        OccupancyGrid(np.zeros((2, 2)), 0.0)
    with pytest.raises(ValueError):
        OccupancyGrid.from_world(World(ROOM), -1.0)
