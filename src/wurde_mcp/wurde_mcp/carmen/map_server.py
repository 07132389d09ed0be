"""``map_server``: CARMEN's map server (Programming with CARMEN 5.1-5.3) for any map a user has.

    map_server [-m MAP] [-s STREAM] [-R RESOLUTION]

``MAP`` is the suite's XML map, a ROS map_server YAML or a CARMEN map (binary or BeeSoft text,
plain or gzip), told by its content (:mod:`wurde_idl.maps`).  Supplies MapServer on ``STREAM``
(default ``MapServer``): the grid map (a grid map's own cells, at its own resolution: 1 occupied,
0 free, -1 unknown as in CARMEN's maps; a wall map's walls drawn at ``-R`` m per cell, default
0.05, over its bounds: 1 occupied, 0 free), its place list and its off-limits regions.  The map is
the stream's info, so a consumer that comes later has it at once
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
from wurde_idl.gridmap import GridMap
from wurde_idl.mapfile import MapData
from wurde_idl.maps import load_any_map

__all__ = ['DEFAULT_RESOLUTION', 'Grid', 'MapServerModule', 'from_grid_map', 'main', 'rasterize']

LOOP_S = 0.1
#: m per grid cell unless told (-R).
DEFAULT_RESOLUTION = 0.05
#: How near a cell's centre a wall must pass (in cells) for the cell to be occupied: half a
#: diagonal, so that a wall never slips between two cells.
_TOUCH = math.sqrt(0.5)


class Grid:
    """A grid: ``cells[iy, ix]`` (0 free, 1 occupied, -1 unknown), cell (0, 0)'s corner at ``origin``."""

    def __init__(self, cells: np.ndarray, origin: tuple[float, float], resolution: float) -> None:
        """Keep the cells.

        :param cells: the cells, row ``iy`` by column ``ix`` (0 free, 1 occupied, -1 unknown).
        :param origin: the map coordinates of cell (0, 0)'s outer corner (m).
        :param resolution: a cell's side (m).
        """
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
    """The walls of ``world`` as a grid over its bounds (or the walls' extent).

    :param world: a wall map; a cell is occupied (1) where a wall passes within half a cell's
        diagonal of its centre, else free (0).
    :param resolution: a cell's side (m).
    :raises ValueError: for a resolution that is not above 0.
    """
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


def from_grid_map(grid_map: GridMap) -> Grid:
    """A grid map file's own cells (nav_msgs/OccupancyGrid's 100, 0, -1) as 1, 0 and -1.

    :param grid_map: the grid of a map file; its origin and resolution are kept.
    """
    cells = np.where(grid_map.cells < 0, -1.0, grid_map.cells / 100.0).astype(np.float32)
    return Grid(cells, (float(grid_map.origin[0]), float(grid_map.origin[1])), float(grid_map.resolution))


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
    """``nav_msgs/OccupancyGrid`` of ``grid`` in frame ``map`` (0 free, 100 occupied).

    :param grid: the served grid (-1 stays unknown).
    """
    message = OccupancyGrid()
    message.header.frame_id = 'map'
    message.info.resolution = float(grid.resolution)
    message.info.width, message.info.height = grid.width, grid.height
    message.info.origin.position.x, message.info.origin.position.y = grid.origin
    message.info.origin.orientation.w = 1.0
    cells = grid.cells.reshape(-1)
    message.data = np.where(cells < 0, -1, cells * 100).astype(np.int8).tolist()
    return message


class MapServerModule:
    """Serves one map: info at start, data again on each request, /map once (transient local)."""

    def __init__(self, manager: CommsManager, world: MapData, grid: Grid, stream: str) -> None:
        """Supply the map and publish it once, as info and on ``map``.

        :param manager: the module's manager (its node publishes ``map``).
        :param world: the map: its name, places and off-limits regions.
        :param grid: its cells (:func:`rasterize` or :func:`from_grid_map`).
        :param stream: the MapServer stream supplied.
        """
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
    """Run ``map_server`` until it is told to quit.

    :param argv: the command line, the program's name first (None: ``sys.argv``).
    :returns: the exit status (2 for a refused map or resolution).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('map_server')
    manager.set_help_string('  -m MAP         the map file: XML, map_server YAML or CARMEN map (default map.xml of\n'
                            '                 the config directory)\n'
                            '  -s STREAM      the MapServer stream supplied (default MapServer)\n'
                            '  -R RESOLUTION  m per grid cell of a wall map (default 0.05; a grid keeps its own)')
    opts = manager.parse_options(argv, 'm:s:R:').user
    try:
        loaded = load_any_map(config_file(manager, opts.get('m'), 'map.xml'))
        world = loaded.data
        resolution = float(opts.get('R', DEFAULT_RESOLUTION))
        grid = rasterize(world, resolution) if loaded.grid is None else from_grid_map(loaded.grid)
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        print(f'map_server: -R: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = MapServerModule(manager, world, grid, opts.get('s', 'MapServer'))
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: {world.name} ({loaded.kind}): {grid.width} x {grid.height} cells of '
                  f'{grid.resolution} m, {len(world.places)} places, {len(world.offlimits)} off-limits regions')
    for note in loaded.notes:
        logger.warn(f'{manager.name}: {world.name}: {note}')
    return run_loop(manager, module.step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
