"""``map_server``: CARMEN's map server (Programming with CARMEN 5.1-5.3) for a WURDE map file.

    map_server [-m MAP] [-s STREAM] [-R RESOLUTION]

Supplies MapServer on ``STREAM`` (default ``MapServer``): the grid map (the map's walls drawn at
``-R`` m per cell, default 0.05, over its bounds: 1 occupied, 0 free), its place list and its
off-limits regions.  The map is the stream's info, so a consumer that comes later has it at once
(CARMEN's ``get_gridmap``, ``get_placelist``, ``get_offlimits``); it is also the stream's data,
published again whenever a consumer writes a request.  Alongside, ``nav_msgs/OccupancyGrid`` on
``map`` (relative: ``/map`` in the root namespace; transient local, frame ``map``, 0/100 per
REP-103's convention) for RViz and Foxglove.  The planner that honours off-limits regions is the
motionModule's (it reads the same map file).
"""

from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np
from nav_msgs.msg import OccupancyGrid
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from wurde_core import CommsManager, Logger, Point, Pose
from wurde_core.interfaces import robot_object_class
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_core.structs import write_members
from wurde_idl.errors import ConfigError
from wurde_idl.mapfile import MapData, load_map_data

__all__ = ['DEFAULT_RESOLUTION', 'Grid', 'MapServerModule', 'main', 'rasterize']

LOOP_S = 0.1
#: m per grid cell unless told (-R).
DEFAULT_RESOLUTION = 0.05
#: How near a cell's centre a wall must pass (in cells) for the cell to be occupied: half a
#: diagonal, so that a wall never slips between two cells.
_TOUCH = math.sqrt(0.5)


class Grid:
    """A grid: ``cells[iy, ix]`` (0 free, 1 occupied), cell (0, 0)'s corner at ``origin``."""

    def __init__(self, cells: np.ndarray, origin: tuple[float, float], resolution: float) -> None:
        self.cells = cells
        self.origin = origin
        self.resolution = resolution

    @property
    def height(self) -> int:
        return int(self.cells.shape[0])

    @property
    def width(self) -> int:
        return int(self.cells.shape[1])


def rasterize(world: MapData, resolution: float) -> Grid:
    """The walls of ``world`` as a grid over its bounds (or the walls' extent)."""
    if not resolution > 0:
        raise ValueError(f'resolution {resolution} must be above 0')
    walls = np.asarray(world.walls, dtype=float).reshape(-1, 4)
    if world.bounds is not None:
        xmin, ymin, xmax, ymax = world.bounds
    elif len(walls):
        xmin, ymin = walls[:, [0, 2]].min(), walls[:, [1, 3]].min()
        xmax, ymax = walls[:, [0, 2]].max(), walls[:, [1, 3]].max()
    else:
        xmin = ymin = 0.0
        xmax = ymax = resolution
    width = max(1, int(math.ceil((xmax - xmin) / resolution - 1e-9)))
    height = max(1, int(math.ceil((ymax - ymin) / resolution - 1e-9)))
    xs = xmin + (np.arange(width) + 0.5) * resolution
    ys = ymin + (np.arange(height) + 0.5) * resolution
    px, py = np.meshgrid(xs, ys)
    occupied = np.zeros((height, width), dtype=bool)
    for x1, y1, x2, y2 in walls:
        dx, dy = x2 - x1, y2 - y1
        length2 = max(dx * dx + dy * dy, 1e-12)
        t = np.clip(((px - x1) * dx + (py - y1) * dy) / length2, 0.0, 1.0)
        occupied |= np.hypot(px - (x1 + t * dx), py - (y1 + t * dy)) <= _TOUCH * resolution
    return Grid(occupied.astype(np.float32), (float(xmin), float(ymin)), resolution)


def _fill(target: Any, world: MapData, grid: Grid) -> None:
    """The map's members of a MapServer info or data struct."""
    values = {
        'map_name': world.name, 'resolution': grid.resolution, 'width': grid.width, 'height': grid.height,
        'origin': Point(*grid.origin), 'cells': [float(v) for v in grid.cells.reshape(-1)],
        'place_names': list(world.places), 'places': [Pose(p.x, p.y, p.theta) for p in world.places.values()],
        'offlimits_sizes': [len(polygon) for polygon in world.offlimits],
        'offlimits_corners': [Point(x, y) for polygon in world.offlimits for x, y in polygon],
    }
    write_members(target, values)


def occupancy_grid(grid: Grid) -> OccupancyGrid:
    """``nav_msgs/OccupancyGrid`` of ``grid`` in frame ``map`` (0 free, 100 occupied)."""
    message = OccupancyGrid()
    message.header.frame_id = 'map'
    message.info.resolution = float(grid.resolution)
    message.info.width, message.info.height = grid.width, grid.height
    message.info.origin.position.x, message.info.origin.position.y = grid.origin
    message.info.origin.orientation.w = 1.0
    message.data = (grid.cells.reshape(-1) * 100).astype(np.int8).tolist()
    return message


class MapServerModule:
    """Serves one map: info at start, data again on each request, /map once (transient local)."""

    def __init__(self, manager: CommsManager, world: MapData, grid: Grid, stream: str) -> None:
        self.world, self.grid = world, grid
        self.obj = robot_object_class('MapServer')(stream)
        manager.register_supplier(self.obj)
        _fill(self.obj.info, world, grid)
        _fill(self.obj.data, world, grid)
        self.obj.publish_info()
        self._published = False
        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.ros = manager.node.create_publisher(OccupancyGrid, 'map', qos)
        self.ros.publish(occupancy_grid(grid))

    def step(self) -> None:
        asked = False
        while self.obj.get_next_request():
            asked = True
        if asked or not self._published:
            self._published = self.obj.publish_data()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('map_server')
    manager.set_help_string('  -m MAP         the map file (default map.xml of the config directory)\n'
                            '  -s STREAM      the MapServer stream supplied (default MapServer)\n'
                            '  -R RESOLUTION  m per grid cell (default 0.05)')
    opts = manager.parse_options(argv, 'm:s:R:').user
    try:
        world = load_map_data(config_file(manager, opts.get('m'), 'map.xml'))
        grid = rasterize(world, float(opts.get('R', DEFAULT_RESOLUTION)))
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        print(f'map_server: -R: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = MapServerModule(manager, world, grid, opts.get('s', 'MapServer'))
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: {world.name}: {grid.width} x {grid.height} cells of {grid.resolution} m, '
                  f'{len(world.places)} places, {len(world.offlimits)} off-limits regions')
    return run_loop(manager, module.step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
