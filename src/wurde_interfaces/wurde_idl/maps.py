"""Any map a user has, chosen by its content: the suite's XML, ROS's map_server YAML + PGM, CARMEN's.

Every program that takes a map (the simulator, poseModule, slamModule's start, the planners, the
navigator, map_server, param_daemon) opens it with :func:`load_map`, so a file is read whatever it
is called:

* the suite's XML map (:mod:`.mapfile`): its walls, places and off-limits regions as written;
* a map_server YAML and the image it names (:mod:`.gridmap`);
* a CARMEN map, binary (``CARMENMAPFILEv020``) or BeeSoft text, plain or gzip (:mod:`.carmen_map`),
  with its places and off-limits regions.

A grid becomes walls along the outlines of its occupied regions (:mod:`.gridwalls`: every wall
within one cell of an occupied region's edge; every region kept, a lone cell as a small loop
round its centre, for in a map a user gives a speck is an obstacle) and bounds that are the
grid's extent; the grid
itself is kept beside them (:attr:`AnyMap.grid`) for those that serve or plan on a grid.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib

from .carmen_map import Polygon, carmen_map_from_bytes, is_carmen_map, read_bytes
from .errors import MapError
from .gridmap import GridMap, load_grid_map
from .gridwalls import grid_walls
from .mapfile import Bounds, MapData, Place, map_data_from_bytes

__all__ = ['AnyMap', 'load_any_map', 'load_map']

#: The map_server YAML keys one of which a YAML map must have.
_YAML_KEYS = (b'image:', b'resolution:', b'origin:')


@dataclasses.dataclass(frozen=True)
class AnyMap:
    """A map as the suite uses it (:attr:`data`), with the grid it came from, if any."""

    data: MapData
    grid: GridMap | None
    kind: str                         # 'xml', 'map_server', 'carmen' or 'beesoft'
    notes: tuple[str, ...] = ()       # what the reader skipped or assumed


def load_map(path: str | os.PathLike[str]) -> MapData:
    """The walls, places, off-limits regions and bounds of the map at ``path`` (any format).

    :param path: an XML map, a map_server YAML, or a CARMEN or BeeSoft map (plain or gzip).
    :raises MapError: naming the file, where and why.
    """
    return load_any_map(path).data


def load_any_map(path: str | os.PathLike[str]) -> AnyMap:
    """Read the map at ``path``, its format told by its content (see the module's description).

    :param path: an XML map, a map_server YAML, or a CARMEN or BeeSoft map (plain or gzip).
    :raises MapError: naming the file, where and why.
    """
    path = os.fspath(path)
    data = read_bytes(path)
    head = data[:4096].lstrip()
    if head.startswith(b'<'):
        return AnyMap(map_data_from_bytes(data, path), None, 'xml')
    if is_carmen_map(data):
        carmen = carmen_map_from_bytes(data, path)       # the bytes already read (and gunzipped)
        return AnyMap(_from_grid(path, carmen.grid, carmen.places, carmen.offlimits), carmen.grid, carmen.kind,
                      carmen.notes)
    if any(key in head for key in _YAML_KEYS):
        grid = load_grid_map(path)
        notes = (f'origin yaw {grid.origin[2]} ignored, as map_server\'s users do',) if grid.origin[2] else ()
        return AnyMap(_from_grid(path, grid, {}, ()), grid, 'map_server', notes)
    raise MapError(path, None, 'not a map this suite reads: neither an XML map, a map_server YAML nor a CARMEN '
                               'map (binary or BeeSoft text, plain or gzip)')


def _from_grid(path: str, grid: GridMap, places: dict[str, Place], offlimits: tuple[Polygon, ...]) -> MapData:
    """The suite's map of a grid: the outlines of its occupied regions as walls."""
    ox, oy = grid.origin[0], grid.origin[1]
    walls = grid_walls(grid.cells, (ox, oy), grid.resolution, min_length=0.0)  # a map's specks are obstacles
    rows, cols = grid.cells.shape
    bounds = Bounds(ox, oy, ox + cols * grid.resolution, oy + rows * grid.resolution)
    name = pathlib.Path(path).name.split('.')[0] or 'map'
    return MapData(name, tuple(map(tuple, walls)), places, offlimits, bounds)
