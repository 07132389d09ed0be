"""The XML map format of the simulated world: reading (strictly) and writing (exactly).

A map is one ``<map>`` element; units are metres and radians, angles counter-clockwise from +x::

    <?xml version="1.0"?>
    <map name="office" version="1.0">
      <bounds xmin="0" ymin="0" xmax="20" ymax="15"/>        <!-- optional -->
      <wall x1="0" y1="6.3" x2="2.05" y2="6.3"/>             <!-- one segment -->
      <polyline points="0,0 20,0 20,15 0,15" closed="true"/> <!-- a chain of segments -->
      <place name="start" x="3" y="7.5" theta="0"/>          <!-- theta optional, 0 -->
      <offlimits points="16,1 19,1 19,3 16,3"/>              <!-- a polygon -->
    </map>

Elements, in any order and number:

``<bounds xmin ymin xmax ymax>``
    at most one; the world's rectangle.  When given, every wall, place and off-limits corner must
    lie inside it.  Without it the bounds are the box around everything in the map.
``<wall x1 y1 x2 y2>``
    a wall segment of non-zero length.
``<polyline points closed>``
    a chain of walls through ``points`` (``"x,y x,y ..."``, at least 2, no point repeated next to
    itself); ``closed="true"`` adds the segment back to the first point (a room or a building;
    then at least 3 points, and do not repeat the first point at the end).  Default false.
``<place name x y theta>``
    a named pose of the place list (CARMEN section 5.2); names are unique, made of letters,
    digits, ``_``, ``-`` and ``.``.
``<offlimits points>``
    an off-limits region (CARMEN section 5.3): a polygon of at least 3 corners with a non-zero
    area, not closed explicitly.  The sensors see through it; planners must not enter it.

Anything else is refused with the file, the line and the reason (:class:`MapError`): unknown
elements or attributes, missing attributes, numbers that do not parse or are not finite, zero-length
walls, duplicate places, too few points, malformed XML, a DOCTYPE with an internal subset (the
suite's hardened parser, :mod:`wurde_idl.safe_xml`).  :func:`save_map` writes every wall as a
``<wall>`` and every number with ``repr``, so ``load_map(save_map(world))`` equals ``world``
exactly.
"""

from __future__ import annotations

import math
import os
import re
import tempfile

import numpy as np
from lxml import etree

from ..errors import ConfigError, MapError
from ..xml_config import Attributes, children, read_root
from .world import Bounds, Place, World, polygon_area

__all__ = ['FORMAT_VERSION', 'load_map', 'save_map']

#: The one version of the format this reader knows.
FORMAT_VERSION = '1.0'

_PLACE_NAME = re.compile(r'^[A-Za-z0-9_][A-Za-z0-9_.\-]*$')


def load_map(path: str | os.PathLike[str]) -> World:
    """Read the map at ``path``.

    :raises MapError: naming the file, the line and the reason for anything the format refuses.
    """
    try:
        return _read(os.fspath(path))
    except MapError:
        raise
    except ConfigError as error:  # from xml_config / safe_xml: same file, line and reason
        raise MapError(error.path, error.line, error.reason) from error


def _read(path: str) -> World:
    root = read_root(path, 'map')
    top = Attributes(path, root, required=('name', 'version'))
    name = top.text('name')
    top.choice('version', (FORMAT_VERSION,))
    walls: list[tuple[float, float, float, float]] = []
    wall_lines: list[int] = []
    places: dict[str, Place] = {}
    place_lines: dict[str, int] = {}
    offlimits: list[np.ndarray] = []
    offlimit_lines: list[int] = []
    bounds: Bounds | None = None
    bounds_line = 0
    for node in children(path, root, ('bounds', 'wall', 'polyline', 'place', 'offlimits')):
        tag = etree.QName(node).localname
        line = node.sourceline or 0
        if tag == 'wall':
            attrs = Attributes(path, node, required=('x1', 'y1', 'x2', 'y2'))
            x1, y1, x2, y2 = (attrs.number(key) for key in ('x1', 'y1', 'x2', 'y2'))
            if (x1, y1) == (x2, y2):
                raise attrs.error(f'<wall> has zero length: both ends at {x1},{y1}')
            walls.append((x1, y1, x2, y2))
            wall_lines.append(line)
        elif tag == 'polyline':
            attrs = Attributes(path, node, required=('points',), optional=('closed',))
            closed = attrs.boolean('closed', False)
            points = _points(attrs, minimum=3 if closed else 2)
            chain = points + points[:1] if closed else points
            for a, b in zip(chain, chain[1:]):
                if a == b:
                    hint = (' (closed="true" already joins the last point to the first)'
                            if closed and b == points[0] else '')
                    raise attrs.error(f'<polyline> repeats the point {a[0]},{a[1]}: a zero-length '
                                      f'wall{hint}')
                walls.append((*a, *b))
                wall_lines.append(line)
        elif tag == 'place':
            attrs = Attributes(path, node, required=('name', 'x', 'y'), optional=('theta',))
            place_name = attrs.text('name')
            if not _PLACE_NAME.match(place_name):
                raise attrs.error(f'place name "{place_name}" may hold only letters, digits, '
                                  f'_, - and .')
            if place_name in places:
                raise attrs.error(f'duplicate place "{place_name}" (first on line '
                                  f'{place_lines[place_name]})')
            places[place_name] = Place(attrs.number('x'), attrs.number('y'),
                                       attrs.number('theta', 0.0))
            place_lines[place_name] = line
        elif tag == 'offlimits':
            attrs = Attributes(path, node, required=('points',))
            corners = _points(attrs, minimum=3)
            if polygon_area(corners) == 0.0:
                raise attrs.error('<offlimits> polygon has zero area')
            offlimits.append(np.array(corners))
            offlimit_lines.append(line)
        else:  # bounds
            if bounds is not None:
                raise MapError(path, line,
                               f'a second <bounds> (the first is on line {bounds_line})')
            attrs = Attributes(path, node, required=('xmin', 'ymin', 'xmax', 'ymax'))
            bounds = Bounds(*(attrs.number(key) for key in ('xmin', 'ymin', 'xmax', 'ymax')))
            if not (bounds.xmin < bounds.xmax and bounds.ymin < bounds.ymax):
                raise attrs.error('<bounds> needs xmin < xmax and ymin < ymax')
            bounds_line = line
    if bounds is not None:
        inside = bounds.contains
        for segment, line in zip(walls, wall_lines):
            if not (inside(*segment[0:2]) and inside(*segment[2:4])):
                raise MapError(path, line,
                               f'wall {segment} leaves the <bounds> of line {bounds_line}')
        for place_name, place in places.items():
            if not inside(place.x, place.y):
                raise MapError(path, place_lines[place_name],
                               f'place "{place_name}" lies outside the <bounds> of line '
                               f'{bounds_line}')
        for corners, line in zip(offlimits, offlimit_lines):
            if not all(inside(x, y) for x, y in corners):
                raise MapError(path, line, f'<offlimits> leaves the <bounds> of line {bounds_line}')
    return World(walls, places=places, offlimits=offlimits, bounds=bounds, name=name)


def _points(attrs: Attributes, *, minimum: int) -> list[tuple[float, float]]:
    """Parse ``points="x,y x,y ..."`` with the file and line of ``attrs`` in every error."""
    raw = attrs.text('points')
    points = []
    for pair in raw.split():
        parts = pair.split(',')
        if len(parts) != 2:
            raise attrs.error(f'points of <{attrs.tag}>: "{pair}" is not x,y')
        try:
            x, y = float(parts[0]), float(parts[1])
        except ValueError as error:
            raise attrs.error(f'points of <{attrs.tag}>: "{pair}" is not a pair of numbers') \
                from error
        if not (math.isfinite(x) and math.isfinite(y)):
            raise attrs.error(f'points of <{attrs.tag}>: "{pair}" is not finite')
        points.append((x, y))
    if len(points) < minimum:
        raise attrs.error(f'<{attrs.tag}> needs at least {minimum} points, got {len(points)}')
    return points


def _number(value: float) -> str:
    """The shortest text that reads back as exactly ``value``."""
    return repr(float(value))


def save_map(world: World, path: str | os.PathLike[str]) -> None:
    """Write ``world`` to ``path`` (atomically: a temporary file renamed over it).

    Every wall becomes one ``<wall>``; numbers are written exactly, bounds always; a world
    without a name is written as ``unnamed`` (the format needs one).
    """
    root = etree.Element('map', name=world.name or 'unnamed', version=FORMAT_VERSION)
    root.text = '\n  '
    items: list[etree._Element] = []
    items.append(etree.Element('bounds', **{key: _number(value) for key, value
                                            in world.bounds._asdict().items()}))
    for x1, y1, x2, y2 in world.walls:
        items.append(etree.Element('wall', x1=_number(x1), y1=_number(y1), x2=_number(x2),
                                   y2=_number(y2)))
    for place_name, place in world.places.items():
        items.append(etree.Element('place', name=place_name, x=_number(place.x),
                                   y=_number(place.y), theta=_number(place.theta)))
    for polygon in world.offlimits:
        items.append(etree.Element('offlimits', points=' '.join(
            f'{_number(x)},{_number(y)}' for x, y in polygon)))
    for index, item in enumerate(items):
        item.tail = '\n' if index == len(items) - 1 else '\n  '
        root.append(item)
    data = etree.tostring(root, xml_declaration=True, encoding='UTF-8')
    target = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(target))
    handle, temporary = tempfile.mkstemp(prefix='.map-', suffix='.xml', dir=directory)
    try:
        with os.fdopen(handle, 'wb') as file:
            file.write(data)
        os.replace(temporary, target)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
