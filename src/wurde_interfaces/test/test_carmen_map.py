"""CARMEN's map files (wurde_idl.carmen_map) and any map by its content (wurde_idl.maps): the
binary chunked format as CARMEN's map_io writes it (plain, gzip, named chunks, old creator ids,
a fork's doubles), BeeSoft's text maps, map_server YAML and the suite's XML, each with the walls a
grid turns into (within one cell of the occupied regions' edges), its places and off-limits
regions; and damaged files refused with the file and the reason, never a traceback."""

from __future__ import annotations

import gzip
import math
import pathlib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wurde_idl.carmen_map import load_carmen_map
from wurde_idl.errors import MapError
from wurde_idl.gridmap import save_grid_map
from wurde_idl.mapfile import MapData, polygon_area, save_map_data
from wurde_idl.maps import load_any_map, load_map
from wurde_testing.carmen_maps import beesoft_map_text, carmen_map_bytes, chunk

RESOLUTION = 0.05


def _room() -> np.ndarray:
    """``probability[x, y]`` of a 5 m x 3 m room: walls all round, a wall inside, an unknown patch."""
    probability = np.zeros((100, 60))
    probability[:, 0] = probability[:, -1] = 1.0
    probability[0, :] = probability[-1, :] = 1.0
    probability[40:42, 10:50] = 0.9                 # x 2.0-2.1 m, y 0.5-2.5 m
    probability[70:90, 30:40] = -1.0                # unknown: no wall of its own
    return probability


PLACES = [(0, 'start', (1.0, 1.5)), (1, 'door', (4.0, 2.0, 1.57)), (2, 'init', (2.5, 1.0, 0.5, 0.1, 0.1, 0.2))]


def _check_room(loaded_data: MapData, cells: np.ndarray) -> None:
    assert cells.shape == (60, 100)                  # rows along y, columns along x
    assert cells[0, 50] == 100 and cells[30, 41] == 100 and cells[30, 20] == 0 and cells[35, 80] == -1
    assert loaded_data.bounds == (0.0, 0.0, 5.0, 3.0)
    walls = np.asarray(loaded_data.walls)
    # The inner wall's two long faces, within a cell of its edges x = 2.0 and 2.1.
    vertical = walls[(np.abs(walls[:, 0] - walls[:, 2]) < RESOLUTION) & (np.abs(walls[:, 1] - walls[:, 3]) > 1.5)]
    faces = sorted((vertical[:, 0] + vertical[:, 2]) / 2)
    assert sum(1.95 <= x <= 2.05 for x in faces) == 1 and sum(2.05 <= x <= 2.15 for x in faces) == 1, faces


def test_a_binary_map_as_map_io_writes_it(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'room.map'
    path.write_bytes(carmen_map_bytes(_room(), RESOLUTION, places=PLACES, points=[(5, 5)],
                                      lines=[(10, 10, 20, 10)], rectangles=[(60, 5, 69, 14)]))
    loaded = load_carmen_map(path)
    assert loaded.kind == 'carmen' and loaded.grid.resolution == RESOLUTION and loaded.notes == ()
    assert loaded.places == {'start': (1.0, 1.5, 0.0), 'door': (4.0, 2.0, 1.57), 'init': (2.5, 1.0, 0.5)}
    point, line, rectangle = loaded.offlimits
    assert polygon_area(point) == pytest.approx(RESOLUTION ** 2)
    assert polygon_area(line) == pytest.approx(11 * RESOLUTION * RESOLUTION)     # ten cells apart, one wide
    assert min(x for x, _ in line) == pytest.approx(0.5) and max(x for x, _ in line) == pytest.approx(1.05)
    assert rectangle == ((3.0, 0.25), (3.5, 0.25), (3.5, 0.75), (3.0, 0.75))
    any_map = load_any_map(path)
    assert any_map.kind == 'carmen' and any_map.data.places == loaded.places
    _check_room(any_map.data, any_map.grid.cells)


def test_gzip_named_chunks_old_creator_ids_and_unknown_chunks(tmp_path: pathlib.Path) -> None:
    laserscans = chunk(16, 'LASERSCANS', b'\0' * 4)
    path = tmp_path / 'room.map.gz'
    path.write_bytes(gzip.compress(carmen_map_bytes(_room(), RESOLUTION, grid_name='floor1', creator_type=0,
                                                    extra=laserscans, places=PLACES[:1])))
    loaded = load_any_map(path)
    assert loaded.data.places == {'start': (1.0, 1.5, 0.0)}
    assert loaded.notes == ("chunk 'LASERSCANS' (type 16) skipped",)
    _check_room(loaded.data, loaded.grid.cells)


def test_a_fork_writing_doubles_is_read_and_said(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'room.map'
    path.write_bytes(carmen_map_bytes(_room(), RESOLUTION, cell_bytes=8, places=PLACES))
    loaded = load_any_map(path)
    assert 'doubles' in loaded.notes[0] and loaded.data.places['door'] == (4.0, 2.0, 1.57)
    _check_room(loaded.data, loaded.grid.cells)


def test_a_beesoft_text_map(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'wean.dat'
    path.write_text(beesoft_map_text(_room(), RESOLUTION * 100))
    loaded = load_any_map(path)
    assert loaded.kind == 'beesoft' and loaded.grid.resolution == RESOLUTION
    _check_room(loaded.data, loaded.grid.cells)


def test_any_map_is_told_by_its_content_not_its_name(tmp_path: pathlib.Path) -> None:
    cells = np.full((60, 100), 0, dtype=np.int8)
    cells[[0, -1], :] = cells[:, [0, -1]] = 100
    save_grid_map(tmp_path / 'grid.yaml', cells, origin=(-1.0, 2.0), resolution=RESOLUTION)
    (tmp_path / 'map.xml').write_bytes(carmen_map_bytes(_room(), RESOLUTION))        # a CARMEN map called .xml
    save_map_data(MapData('walls', ((0.0, 0.0, 1.0, 0.0),), {'start': (0.5, 0.5, 0.0)}), tmp_path / 'walls.map')
    yaml_map = load_any_map(tmp_path / 'grid.yaml')
    assert yaml_map.kind == 'map_server' and yaml_map.data.bounds == pytest.approx((-1.0, 2.0, 4.0, 5.0))
    assert len(yaml_map.data.walls) == 8                    # the ring's outer and inner sides
    assert load_any_map(tmp_path / 'map.xml').kind == 'carmen'
    assert load_map(tmp_path / 'walls.map').places == {'start': (0.5, 0.5, 0.0)}


@pytest.mark.parametrize('seed', range(6))
def test_walls_lie_within_a_cell_of_the_occupied_regions_edges(tmp_path: pathlib.Path, seed: int) -> None:
    """Random rooms of boxes: every wall point is within one cell of an occupied cell's edge, and
    every occupied cell next to a free one is within one cell of a wall."""
    rng = np.random.default_rng(seed)
    probability = np.zeros((120, 90))
    probability[:, [0, -1]] = probability[[0, -1], :] = 1.0
    for _ in range(6):
        x, y = rng.integers(5, 100), rng.integers(5, 70)
        probability[x:x + rng.integers(1, 15), y:y + rng.integers(1, 15)] = rng.uniform(0.6, 1.0)
    path = tmp_path / 'boxes.map'
    path.write_bytes(carmen_map_bytes(probability, RESOLUTION))
    loaded = load_any_map(path)
    occupied = np.argwhere(loaded.grid.cells == 100)                  # (row, col)
    centres = (occupied[:, ::-1] + 0.5) * RESOLUTION
    walls = np.asarray(loaded.data.walls)
    samples = np.vstack([walls[:, :2] + t * (walls[:, 2:] - walls[:, :2]) for t in np.linspace(0, 1, 11)])
    to_cell = np.abs(samples[:, None, :] - centres[None, :, :]).max(axis=2).min(axis=1)
    assert to_cell.max() <= 1.5 * RESOLUTION + 1e-9               # inside or within a cell of the edge
    edge = [(r, c) for r, c in occupied if (loaded.grid.cells[max(r - 1, 0):r + 2, max(c - 1, 0):c + 2] == 0).any()]
    edge_centres = (np.asarray(edge)[:, ::-1] + 0.5) * RESOLUTION
    starts, ends = walls[:, :2], walls[:, 2:]
    direction = ends - starts
    t = np.clip(((edge_centres[:, None, :] - starts) * direction).sum(axis=2) / (direction ** 2).sum(axis=1), 0, 1)
    nearest = starts + t[..., None] * direction
    assert np.hypot(*(edge_centres[:, None, :] - nearest).transpose(2, 0, 1)).min(axis=1).max() <= 1.5 * RESOLUTION


def test_maps_that_are_wrong_are_refused_with_the_file_and_the_reason(tmp_path: pathlib.Path) -> None:
    good = carmen_map_bytes(_room(), RESOLUTION, places=PLACES)
    cases = {
        'cut.map': (good[:len(good) // 2], 'claims'),
        'gz.map': (gzip.compress(good)[:200], 'damaged gzip'),
        'nogrid.map': (good[:good.index(b'CARMENMAPFILEv020') + 17], 'without a GRIDMAP'),
        'text.map': (b'hello\n', 'not a map this suite reads'),
        'bee.dat': (b'robot_specifications->resolution 5\nglobal_map[0]: 3 3\n1 1 1\n', 'cut short'),
    }
    for name, (data, reason) in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(MapError) as caught:
            load_any_map(tmp_path / name)
        assert caught.value.path.endswith(name) and reason in str(caught.value), (name, str(caught.value))
    with pytest.raises(MapError, match='cannot read'):
        load_any_map(tmp_path / 'missing.map')


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.data())
def test_damaged_binary_maps_are_refused_or_read_never_a_traceback(tmp_path: pathlib.Path, data: st.DataObject) -> None:
    good = bytearray(carmen_map_bytes(_room()[:20, :10], RESOLUTION, places=PLACES, rectangles=[(1, 1, 3, 3)]))
    cut = data.draw(st.integers(0, len(good)))
    flips = data.draw(st.lists(st.tuples(st.integers(0, len(good) - 1), st.integers(0, 255)), max_size=4))
    for at, value in flips:
        good[at] = value
    path = tmp_path / 'damaged.map'
    path.write_bytes(bytes(good[:cut]))
    try:
        loaded = load_any_map(path)
    except MapError as error:
        assert error.path == str(path)
    else:
        assert loaded.grid is None or all(math.isfinite(v) for v in loaded.data.bounds)
