"""The suite's map file format: reading (strictly) and writing (exactly), in pure Python.

One home for the format that the simulator (``wurde_drivers.sim``), Pluto's poseModule (a-priori
maps) and slamModule (saved maps) and a CARMEN map-server bridge all read, so none of them imports
another (docs/design.md, "Who may import whom").  The model is CARMEN's (programming-with-carmen.txt,
section 5): walls, a place list (5.2) and off-limits regions (5.3).  Units are metres and radians,
angles counter-clockwise from +x (REP-103); config/maps/README.md documents the format::

    <?xml version="1.0"?>
    <map name="office" version="1.0">
      <bounds xmin="0" ymin="0" xmax="20" ymax="15"/>        <!-- optional, at most one -->
      <wall x1="0" y1="6.3" x2="2.05" y2="6.3"/>             <!-- one segment -->
      <polyline points="0,0 20,0 20,15 0,15" closed="true"/> <!-- a chain of segments -->
      <place name="start" x="3" y="7.5" theta="0"/>          <!-- theta optional, 0 -->
      <offlimits points="16,1 19,1 19,3 16,3"/>              <!-- a polygon -->
    </map>

docs/wurde-core.md lists everything the reader refuses.

:func:`load_map_data` gives a :class:`MapData` (polylines split into walls) and refuses anything
else with the file, the line and the reason (:class:`MapError`; the hardened parser,
:mod:`wurde_idl.safe_xml`); :func:`save_map_data` reads its own text back before it touches the
file, so what it writes always loads equal.  No numpy here: a bridge or a test needs only lxml.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import tempfile
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import NamedTuple

from lxml import etree

from .errors import ConfigError, MapError
from .safe_xml import parse_bytes, parse_file
from .xml_elements import Attributes, children, local_name

__all__ = ['FORMAT_VERSION', 'Bounds', 'MapData', 'MapError', 'Place', 'load_map_data',
           'map_data_from_bytes', 'map_data_to_bytes', 'polygon_area', 'save_map_data']

#: The one version of the format this reader knows.
FORMAT_VERSION = '1.0'

#: Letters, digits, ``_``, ``-`` and ``.``; not starting with ``-`` or ``.``.
PLACE_NAME = re.compile(r'^[A-Za-z0-9_][A-Za-z0-9_.\-]*$')

_ELEMENTS = ('bounds', 'wall', 'polyline', 'place', 'offlimits')

Wall = tuple[float, float, float, float]
Point = tuple[float, float]


class Place(NamedTuple):
    """A named pose of the place list (CARMEN's ``carmen_place_t``): metres and radians."""

    x: float
    y: float
    theta: float = 0.0


class Bounds(NamedTuple):
    """The rectangle a map occupies, in metres."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float

    def contains(self, x: float, y: float) -> bool:
        """Whether ``(x, y)`` lies inside the rectangle or on its edge.

        :param x: m.
        :param y: m.
        """
        return self.xmin <= x <= self.xmax and self.ymin <= y <= self.ymax


def polygon_area(polygon: Iterable[Sequence[float]]) -> float:
    """Signed area of a simple polygon given as ``(x, y)`` corners (shoelace; positive when CCW).

    :param polygon: the corners, not closed explicitly: any iterable of pairs, a ``(K, 2)``
        numpy array included.
    """
    points = [(float(x), float(y)) for x, y in polygon]
    twice = sum(x1 * y2 - x2 * y1 for (x1, y1), (x2, y2) in zip(points, points[1:] + points[:1]))
    return 0.5 * twice


@dataclasses.dataclass(frozen=True)
class MapData:
    """Everything a map file holds, as plain Python values (no numpy).

    The constructor takes any sequences and numbers and stores tuples of floats, :class:`Place`
    and :class:`Bounds`; it does not judge the geometry (that is the reader's job, and
    :func:`save_map_data` refuses what the reader would refuse).

    :param name: the map's name.
    :param walls: segments ``(x1, y1, x2, y2)``; a file's ``<polyline>`` arrives as its segments.
    :param places: name -> :class:`Place` (or ``(x, y)`` / ``(x, y, theta)``), in file order.
    :param offlimits: polygons, each a tuple of ``(x, y)`` corners, not closed explicitly.
    :param bounds: ``(xmin, ymin, xmax, ymax)``, or ``None`` when the file has no ``<bounds>``.
    """

    name: str
    walls: tuple[Wall, ...] = ()
    places: Mapping[str, Place] = dataclasses.field(default_factory=dict)
    offlimits: tuple[tuple[Point, ...], ...] = ()
    bounds: Bounds | None = None

    __hash__ = None  # type: ignore[assignment]  # holds a dict: compare, don't hash

    def __post_init__(self) -> None:
        walls = tuple(_floats(wall, 4, 'a wall') for wall in self.walls)
        places = {str(key): Place(*(float(v) for v in pose)) for key, pose in self.places.items()}
        offlimits = tuple(tuple(_floats(corner, 2, 'a corner') for corner in polygon)
                          for polygon in self.offlimits)
        bounds = None if self.bounds is None else Bounds(*_floats(self.bounds, 4, 'bounds'))
        for field, value in (('walls', walls), ('places', places), ('offlimits', offlimits),
                             ('bounds', bounds)):
            object.__setattr__(self, field, value)


def _floats(values: Iterable[float], count: int, what: str) -> tuple[float, ...]:
    numbers = tuple(float(v) for v in values)
    if len(numbers) != count:
        raise ValueError(f'{what} needs {count} numbers, got {len(numbers)}')
    return numbers


# -- reading -------------------------------------------------------------------------------------

def load_map_data(path: str | os.PathLike[str]) -> MapData:
    """Read the map file at ``path``.

    :param path: an XML map file of the suite's format.
    :raises MapError: naming the file, the line and the reason for anything the format refuses
        (and for a file that cannot be read).
    """
    path = os.fspath(path)
    return _checked(path, lambda: parse_file(path, root_tag='map', error=MapError))


def map_data_from_bytes(data: bytes, path: str | os.PathLike[str] = '<bytes>') -> MapData:
    """Read a map from the bytes of a file.

    :param data: the file's bytes.
    :param path: names the source in errors only.
    :raises MapError: as :func:`load_map_data`.
    """
    path = os.fspath(path)
    return _checked(path, lambda: parse_bytes(data, path, root_tag='map', error=MapError))


def _checked(path: str, parse: Callable[[], etree._Element]) -> MapData:
    try:
        return _read(path, parse())
    except MapError:
        raise
    except ConfigError as error:  # from xml_elements: same file, line and reason
        raise MapError(error.path, error.line, error.reason) from error


def _read(path: str, root: etree._Element) -> MapData:
    top = Attributes(path, root, required=('name', 'version'))
    name = top.text('name')
    top.choice('version', (FORMAT_VERSION,))
    walls: list[Wall] = []
    wall_lines: list[int] = []
    places: dict[str, Place] = {}
    place_lines: dict[str, int] = {}
    offlimits: list[tuple[Point, ...]] = []
    offlimit_lines: list[int] = []
    bounds: Bounds | None = None
    bounds_line = 0
    for node in children(path, root, _ELEMENTS):
        tag = local_name(node)
        line = node.sourceline or 0
        if tag == 'wall':
            attrs = Attributes(path, node, required=('x1', 'y1', 'x2', 'y2'))
            x1, y1, x2, y2 = (attrs.number(key) for key in ('x1', 'y1', 'x2', 'y2'))
            if (x1, y1) == (x2, y2):
                raise attrs.error(f'<wall> has zero length: both ends at {x1},{y1}')
            walls.append((x1, y1, x2, y2))
            wall_lines.append(line)
        elif tag == 'polyline':
            for segment in _polyline(Attributes(path, node, required=('points',),
                                                optional=('closed',))):
                walls.append(segment)
                wall_lines.append(line)
        elif tag == 'place':
            place_name, place = _place(Attributes(path, node, required=('name', 'x', 'y'),
                                                  optional=('theta',)))
            if place_name in places:
                raise MapError(path, line, f'duplicate place "{place_name}" (first on line '
                                           f'{place_lines[place_name]})')
            places[place_name] = place
            place_lines[place_name] = line
        elif tag == 'offlimits':
            attrs = Attributes(path, node, required=('points',))
            corners = _points(attrs, minimum=3)
            if polygon_area(corners) == 0.0:
                raise attrs.error('<offlimits> polygon has zero area')
            offlimits.append(tuple(corners))
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
        _check_inside(path, bounds, bounds_line, zip(walls, wall_lines),
                      ((n, p, place_lines[n]) for n, p in places.items()),
                      zip(offlimits, offlimit_lines))
    return MapData(name, tuple(walls), places, tuple(offlimits), bounds)


def _polyline(attrs: Attributes) -> list[Wall]:
    """The segments of one ``<polyline>``; a repeated point is a zero-length wall."""
    closed = attrs.boolean('closed', False)
    points = _points(attrs, minimum=3 if closed else 2)
    chain = points + points[:1] if closed else points
    segments = []
    for a, b in zip(chain, chain[1:]):
        if a == b:
            hint = (' (closed="true" already joins the last point to the first)'
                    if closed and b == points[0] else '')
            raise attrs.error(f'<polyline> repeats the point {a[0]},{a[1]}: a zero-length '
                              f'wall{hint}')
        segments.append((*a, *b))
    return segments


def _place(attrs: Attributes) -> tuple[str, Place]:
    place_name = attrs.text('name')
    if not PLACE_NAME.match(place_name):
        raise attrs.error(f'place name "{place_name}" may hold only letters, digits, _, - and .')
    return place_name, Place(attrs.number('x'), attrs.number('y'), attrs.number('theta', 0.0))


def _check_inside(path: str, bounds: Bounds, bounds_line: int,
                  walls: Iterable[tuple[Wall, int]],
                  places: Iterable[tuple[str, Place, int]],
                  offlimits: Iterable[tuple[tuple[Point, ...], int]]) -> None:
    """Refuse the first wall, place or off-limits corner that lies outside ``bounds``."""
    inside = bounds.contains
    for segment, line in walls:
        if not (inside(*segment[0:2]) and inside(*segment[2:4])):
            raise MapError(path, line, f'wall {segment} leaves the <bounds> of line {bounds_line}')
    for place_name, place, line in places:
        if not inside(place.x, place.y):
            raise MapError(path, line, f'place "{place_name}" lies outside the <bounds> of line '
                                       f'{bounds_line}')
    for corners, line in offlimits:
        if not all(inside(x, y) for x, y in corners):
            raise MapError(path, line, f'<offlimits> leaves the <bounds> of line {bounds_line}')


def _points(attrs: Attributes, *, minimum: int) -> list[Point]:
    """Parse ``points="x,y x,y ..."`` with the file and line of ``attrs`` in every error."""
    points = []
    for pair in attrs.text('points').split():
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


# -- writing -------------------------------------------------------------------------------------

def _number(value: float) -> str:
    """The shortest text that reads back as exactly ``value``."""
    return repr(float(value))


def map_data_to_bytes(data: MapData) -> bytes:
    """The text of the map file for ``data`` (UTF-8, with an XML declaration).

    A map without a name is written as ``unnamed`` (the format needs one).  No checks: see
    :func:`save_map_data`.

    :param data: the map.
    """
    root = etree.Element('map', name=data.name or 'unnamed', version=FORMAT_VERSION)
    root.text = '\n  '
    items: list[etree._Element] = []
    if data.bounds is not None:
        items.append(etree.Element('bounds', **{key: _number(value) for key, value
                                                in data.bounds._asdict().items()}))
    for x1, y1, x2, y2 in data.walls:
        items.append(etree.Element('wall', x1=_number(x1), y1=_number(y1), x2=_number(x2),
                                   y2=_number(y2)))
    for place_name, place in data.places.items():
        items.append(etree.Element('place', name=place_name, x=_number(place.x),
                                   y=_number(place.y), theta=_number(place.theta)))
    for polygon in data.offlimits:
        items.append(etree.Element('offlimits', points=' '.join(
            f'{_number(x)},{_number(y)}' for x, y in polygon)))
    for index, item in enumerate(items):
        item.tail = '\n' if index == len(items) - 1 else '\n  '
        root.append(item)
    return etree.tostring(root, xml_declaration=True, encoding='UTF-8')


def save_map_data(data: MapData, path: str | os.PathLike[str]) -> None:
    """Write ``data`` to ``path`` (atomically: a temporary file renamed over it).

    The text is read back first, so a map the reader would refuse (a zero-length wall, a place
    name with a space, a place outside the bounds, ...) is never written, and what is written
    loads equal to ``data`` (a nameless map loads as ``unnamed``).

    :param data: the map.
    :param path: the file written.
    :raises ValueError: ``data`` cannot be written so that it reads back equal; says why.
    :raises OSError: the file cannot be written.
    """
    target = os.fspath(path)
    text = map_data_to_bytes(data)
    expected = dataclasses.replace(data, name=data.name or 'unnamed')
    try:
        again = map_data_from_bytes(text, target)
    except MapError as error:
        raise ValueError(f'map {expected.name!r} would not read back: {error.reason}') from error
    if again != expected:
        raise ValueError(f'map {expected.name!r} would not read back equal (names or place '
                         f'names with surrounding spaces?)')
    directory = os.path.dirname(os.path.abspath(target))
    handle, temporary = tempfile.mkstemp(prefix='.map-', suffix='.xml', dir=directory)
    try:
        with os.fdopen(handle, 'wb') as file:
            file.write(text)
        os.replace(temporary, target)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
