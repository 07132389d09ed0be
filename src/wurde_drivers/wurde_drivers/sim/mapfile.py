"""Map files of the simulated world: the suite's map format read into, and written from, a World.

The format, its strict reader and its exact writer live in :mod:`wurde_idl.mapfile` (Pluto's
modules read the same files and may not import this package); this module only turns their
:class:`~wurde_idl.mapfile.MapData` into a :class:`~.world.World` and back.  A map::

    <?xml version="1.0"?>
    <map name="office" version="1.0">
      <bounds xmin="0" ymin="0" xmax="20" ymax="15"/>        <!-- optional -->
      <wall x1="0" y1="6.3" x2="2.05" y2="6.3"/>             <!-- one segment -->
      <polyline points="0,0 20,0 20,15 0,15" closed="true"/> <!-- a chain of segments -->
      <place name="start" x="3" y="7.5" theta="0"/>          <!-- theta optional, 0 -->
      <offlimits points="16,1 19,1 19,3 16,3"/>              <!-- a polygon -->
    </map>

Elements, attributes and everything the reader refuses (with file, line and reason,
:class:`~wurde_idl.errors.MapError`): :mod:`wurde_idl.mapfile` and ``config/maps/README.md``.
The simulator also runs in a map_server YAML or a CARMEN map (:mod:`wurde_idl.maps`, told by
content): the grid's outlines are its walls.
"""

from __future__ import annotations

import os

from wurde_idl import maps
from wurde_idl.mapfile import FORMAT_VERSION, save_map_data

from .world import World

__all__ = ['FORMAT_VERSION', 'load_map', 'save_map']


def load_map(path: str | os.PathLike[str]) -> World:
    """Read the map at ``path`` (any format :func:`wurde_idl.maps.load_map` reads) into a
    :class:`~.world.World`.

    :raises MapError: naming the file, the line and the reason for anything the format refuses.
    """
    return World.from_map_data(maps.load_map(path))


def save_map(world: World, path: str | os.PathLike[str]) -> None:
    """Write ``world`` to ``path`` (atomically), so that :func:`load_map` gives back an equal world.

    Every wall becomes one ``<wall>``; numbers are written exactly, bounds always; a world
    without a name is written as ``unnamed`` (the format needs one).

    :raises ValueError: the world holds what the format cannot (a place name with a space).
    """
    save_map_data(world.to_map_data(), path)
