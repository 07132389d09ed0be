"""CARMEN's map server (wurde_mcp.carmen.map_server): the walls drawn on the grid with no gap, and the
real module serving the shipped office map — grid, places and off-limits region as the stream's info
to a consumer that comes later, the data again on request, and nav_msgs/OccupancyGrid on /map — and
param_daemon given the map, which serves it the same way (CARMEN's daemon served its map); a
CARMEN map served with its own grid."""

from __future__ import annotations

import gzip
import math
import os
import pathlib
import time

import numpy as np
import pytest
from nav_msgs.msg import OccupancyGrid
from wurde_core import CommsManager
from wurde_core.interfaces import MapServer
from wurde_idl.mapfile import MapData, load_map_data
from wurde_testing import ChildProcess, find_executable
from wurde_testing.carmen_maps import carmen_map_bytes
from wurde_testing.topics import latched

from wurde_mcp.carmen.map_server import rasterize

ROOT = pathlib.Path(__file__).resolve().parents[3]
OFFICE = ROOT / 'config' / 'maps' / 'office.xml'
DEADLINE = 30.0


def test_a_slanted_wall_is_drawn_without_gaps_and_free_space_stays_free() -> None:
    world = MapData('box', walls=[(0.0, 0.0, 4.0, 3.0)], bounds=(0.0, 0.0, 4.0, 3.0))
    grid = rasterize(world, 0.1)
    assert (grid.width, grid.height) == (40, 30)
    for t in np.linspace(0.0, 1.0, 400):                   # every point of the wall is in an occupied cell
        x, y = 4.0 * t, 3.0 * t
        assert grid.cells[min(int(y / 0.1), 29), min(int(x / 0.1), 39)] == 1.0
    assert grid.cells[25, 5] == 0.0 and grid.cells[5, 35] == 0.0
    with pytest.raises(ValueError):
        rasterize(world, 0.0)


def _until(manager: CommsManager, server: ChildProcess, predicate, what: str) -> None:  # type: ignore[no-untyped-def]
    """Step the client until ``predicate()``, failing if the server exits or the deadline passes."""
    deadline = time.monotonic() + DEADLINE
    while not predicate():
        assert server.process.poll() is None, f'{what}: the server exited: {server.stderr}'
        assert time.monotonic() < deadline, f'{what}: not within {DEADLINE} s'
        manager.step()
        manager.wait(0.05)


SERVERS = {'map_server': ['map_server', '-m', str(OFFICE), '-R', '0.1'],
           'param_daemon': ['param_daemon', '-R', 'pluto', '-M', '0.1', str(OFFICE),
                            str(ROOT / 'config' / 'carmen' / 'carmen.ini')]}


@pytest.mark.parametrize('program', sorted(SERVERS))
def test_the_module_serves_the_office_map_to_late_consumers_and_on_request(ros_domain: int, program: str,
                                                                          tmp_path: pathlib.Path) -> None:
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    world = load_map_data(OFFICE)
    name, *args = SERVERS[program]
    with ChildProcess([find_executable('wurde_mcp', name), *args], env=env) as server:
        manager = CommsManager('MapClient')
        manager.set_no_sleep()
        maps = MapServer('MapServer')
        manager.register_consumer(maps)
        try:
            def until(predicate, what: str) -> None:
                _until(manager, server, predicate, what)

            until(maps.get_next_info, 'the map as info (transient local)')
            info = maps.info
            assert info.map_name.get_value() == world.name
            assert (info.width.get_value(), info.height.get_value()) == (200, 150)    # 20 m x 15 m at 0.1 m
            cells = np.asarray(info.cells.get_value()).reshape(150, 200)
            assert cells[0, 100] == 1.0 and cells[75, 30] == 0.0 and cells.mean() < 0.2   # outer wall; the start place
            places = dict(zip(info.place_names.get_value(), info.places.get_value()))
            assert set(places) == set(world.places)
            assert math.isclose(places['office2'].x(), 7.5) and math.isclose(places['office2'].y(), 3.0)
            assert list(info.offlimits_sizes.get_value()) == [4]
            assert [(p.x(), p.y()) for p in info.offlimits_corners.get_value()] == list(world.offlimits[0])
            # A request: the map again as data.
            until(lambda: maps.peers('request') > 0, 'the request channel matched')
            maps.requests.map_name.set_value('')
            assert maps.publish_request()
            until(maps.get_next_data, 'the map as data after a request')
            assert maps.data.width == 200
        finally:
            manager.clean_up()

        # /map for RViz and Foxglove: transient local, so this late subscriber gets it.
        grid = latched('/map', OccupancyGrid, DEADLINE)
        assert grid.header.frame_id == 'map' and (grid.info.width, grid.info.height) == (200, 150)
        assert math.isclose(grid.info.resolution, 0.1, rel_tol=1e-6) and set(grid.data) == {0, 100}


@pytest.mark.parametrize('program', ['map_server', 'param_daemon'])
def test_a_carmen_map_is_served_with_its_own_grid_places_and_off_limits(ros_domain: int, program: str,
                                                                       tmp_path: pathlib.Path) -> None:
    """A gzip CARMEN map (CARMEN's map_io layout) named like anything: its own cells at its own
    resolution (unknown stays unknown: -1 in MapServer and on /map), its places and off-limits."""
    probability = np.zeros((80, 40))                         # [x, y]: 8 m x 4 m at 0.1 m
    probability[:, [0, -1]] = probability[[0, -1], :] = 1.0
    probability[60:70, 10:20] = -1.0
    path = tmp_path / 'lab'                                  # no suffix: told by content
    path.write_bytes(gzip.compress(carmen_map_bytes(probability, 0.1, places=[(1, 'desk', (2.0, 1.5, 0.5))],
                                                    rectangles=[(30, 5, 39, 14)])))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    command = {'map_server': ['map_server', '-m', str(path)],
               'param_daemon': ['param_daemon', '-R', 'pluto', str(path),
                                str(ROOT / 'config' / 'carmen' / 'carmen.ini')]}
    name, *args = command[program]
    with ChildProcess([find_executable('wurde_mcp', name), *args], env=env) as server:
        manager = CommsManager('MapClient')
        manager.set_no_sleep()
        maps = MapServer('MapServer')
        manager.register_consumer(maps)
        try:
            _until(manager, server, maps.get_next_info, 'the map as info (transient local)')
            info = maps.info
            assert info.map_name.get_value() == 'lab' and math.isclose(info.resolution.get_value(), 0.1, rel_tol=1e-6)
            cells = np.asarray(info.cells.get_value()).reshape(info.height.get_value(), info.width.get_value())
            assert cells.shape == (40, 80) and cells[0, 40] == 1.0 and cells[20, 20] == 0.0 and cells[15, 65] == -1.0
            places = dict(zip(info.place_names.get_value(), info.places.get_value()))
            assert math.isclose(places['desk'].x(), 2.0) and math.isclose(places['desk'].theta(), 0.5)
            corners = [c for p in info.offlimits_corners.get_value() for c in (p.x(), p.y())]
            assert corners == pytest.approx([3.0, 0.5, 4.0, 0.5, 4.0, 1.5, 3.0, 1.5])
        finally:
            manager.clean_up()
        grid = latched('/map', OccupancyGrid, DEADLINE)
        assert (grid.info.width, grid.info.height) == (80, 40) and set(grid.data) == {-1, 0, 100}
        if program == 'map_server':
            assert 'lab (carmen)' in server.stderr or 'lab (carmen)' in server.stdout
