"""CARMEN's map files, read without CARMEN: the chunked binary format and BeeSoft's text grids.

Programming with CARMEN 5.1-5.3 (the map server serves a grid, a place list and off-limits
regions) keeps them in one ``.map`` file, plain or gzip (CARMEN opens both alike), as its map_io
writes it: a ``#`` comment header, ``CARMENMAPFILEv020``, then typed chunks (``GRIDMAP``,
``OFFLIMITS``, ``PLACES``; the others skipped by their size, only the first of each kind read, as
CARMEN's readers do).  The older BeeSoft (Rhino) text map CARMEN's tools converted from is read
too.  docs/wurde-core.md ("wurde_idl.carmen_map") lays out both formats byte by byte; a test
writes files as map_io does (:mod:`wurde_testing.carmen_maps`), so change the two together.

What is read becomes a :class:`~wurde_idl.gridmap.GridMap` (nav_msgs/OccupancyGrid's cells:
occupied above :data:`OCCUPIED_PROBABILITY`, free at or below it, -1 unknown), the places and the
off-limits regions as polygons in metres (a point becomes its cell, a line the cells along it, a
rectangle the cells it spans).  Anything malformed is refused with the file, the byte offset (or
line) and the reason (:class:`~wurde_idl.errors.MapError`).
"""

from __future__ import annotations

import dataclasses
import gzip
import math
import os
import re
import struct
import zlib

import numpy as np

from .errors import MapError
from .gridmap import GridMap
from .mapfile import Place

__all__ = ['CarmenMap', 'OCCUPIED_PROBABILITY', 'carmen_map_from_bytes', 'is_carmen_map', 'load_carmen_map',
           'read_bytes']

LABEL = b'CARMENMAPFILEv020'
GRIDMAP, OFFLIMITS, PLACES, CREATOR = 1, 2, 4, 32
NAMED_FLAG = 0x80
#: A cell is occupied when its probability is above this (CARMEN's maps hold probabilities).
OCCUPIED_PROBABILITY = 0.5
#: The largest map read (cells): 20 000 x 20 000, far beyond any building.
MAX_CELLS = 400_000_000
_BEESOFT = re.compile(rb'^\s*(robot_specifications->|global_map\[0\])', re.MULTILINE)

Polygon = tuple[tuple[float, float], ...]


@dataclasses.dataclass(frozen=True)
class CarmenMap:
    """What a CARMEN (or BeeSoft) map file holds."""

    grid: GridMap
    places: dict[str, Place]
    offlimits: tuple[Polygon, ...]
    kind: str                                    # 'carmen' or 'beesoft'
    notes: tuple[str, ...] = ()                  # what was skipped or assumed, said once each


def read_bytes(path: str) -> bytes:
    """The file's bytes, gunzipped if it is gzip (CARMEN's carmen_fopen reads both alike).

    :param path: the file.
    :raises MapError: when it cannot be read or its gzip stream is damaged.
    """
    try:
        with open(path, 'rb') as file:
            data = file.read()
    except OSError as error:
        raise MapError(path, None, f'cannot read: {error.strerror or error}') from error
    if data[:2] == b'\x1f\x8b':
        try:
            return gzip.decompress(data)
        except (OSError, EOFError, zlib.error) as error:
            raise MapError(path, None, f'a damaged gzip stream: {error}') from error
    return data


def is_carmen_map(data: bytes) -> bool:
    """Whether ``data`` is a CARMEN binary map or a BeeSoft text map (by its header).

    :param data: a file's bytes, gunzipped (:func:`read_bytes`).
    """
    return _label_offset(data) is not None or _BEESOFT.search(data[:4096]) is not None


def load_carmen_map(path: str | os.PathLike[str]) -> CarmenMap:
    """Read a CARMEN map file (either format, plain or gzip).

    :param path: the ``.map`` file.
    :raises MapError: naming the file, where and why.
    """
    path = os.fspath(path)
    return carmen_map_from_bytes(read_bytes(path), path)


def carmen_map_from_bytes(data: bytes, path: str = '<bytes>') -> CarmenMap:
    """Read a CARMEN map from a file's bytes.

    :param data: the bytes, gunzipped (:func:`read_bytes`).
    :param path: names the source in errors only.
    :raises MapError: naming the file, where and why.
    """
    offset = _label_offset(data)
    if offset is not None:
        return _ChunkReader(path, data, offset + len(LABEL)).read()
    if _BEESOFT.search(data[:4096]):
        return _beesoft(path, data)
    raise MapError(path, None, f'not a CARMEN map: no {LABEL.decode()} after the # comments and no BeeSoft '
                               f'global_map[0] header')


def _label_offset(data: bytes) -> int | None:
    """Where the label starts after the comment lines (carmen_map_read_comment_chunk), if it does."""
    offset = 0
    while data[offset:offset + 1] == b'#':
        end = data.find(b'\n', offset)
        if end < 0:
            return None
        offset = end + 1
    return offset if data[offset:offset + len(LABEL)] == LABEL else None


class _ChunkReader:
    """The chunks of a binary CARMEN map, from ``offset`` on."""

    def __init__(self, path: str, data: bytes, offset: int) -> None:
        self.path, self.data, self.offset = path, data, offset
        self.notes: list[str] = []

    def error(self, at: int, reason: str) -> MapError:
        return MapError(self.path, None, f'byte {at}: {reason}')

    def read(self) -> CarmenMap:
        grid = places = offlimits = None
        seen: set[int] = set()
        while self.offset < len(self.data):
            start = self.offset
            if len(self.data) - start < 15:
                raise self.error(start, f'a chunk header cut short ({len(self.data) - start} bytes left)')
            kind = self.data[start] & ~NAMED_FLAG
            (size,) = struct.unpack_from('<i', self.data, start + 1)
            body = start + 5 + 10
            end = start + 5 + size
            if size < 10 or end > len(self.data):
                raise self.error(start, f'chunk {self._description(start)!r} (type {kind}) claims {size} bytes; '
                                        f'{len(self.data) - start - 5} are left')
            if self.data[start] & NAMED_FLAG:
                nul = self.data.find(b'\0', body, end)
                if nul < 0:
                    raise self.error(body, 'a named chunk whose name has no NUL')
                body = nul + 1
            self.offset = end
            if kind in seen:
                self.notes.append(f'a second chunk of type {kind} at byte {start} skipped (CARMEN reads the first)')
                continue
            seen.add(kind)
            if kind == GRIDMAP:
                grid = self._gridmap(body, end)
            elif kind == PLACES:
                places = self._places(body, end)
            elif kind == OFFLIMITS:
                offlimits = body, end
            elif kind not in (CREATOR, 0):
                self.notes.append(f'chunk {self._description(start)!r} (type {kind}) skipped')
        if grid is None:
            raise MapError(self.path, None, 'a CARMEN map without a GRIDMAP chunk')
        polygons = self._offlimits(*offlimits, grid.resolution) if offlimits else ()
        return CarmenMap(grid, places or {}, polygons, 'carmen', tuple(self.notes))

    def _description(self, start: int) -> str:
        return self.data[start + 5:start + 15].decode('latin-1').strip()

    def _gridmap(self, body: int, end: int) -> GridMap:
        if end - body < 12:
            raise self.error(body, 'GRIDMAP chunk too short for its sizes')
        size_x, size_y = struct.unpack_from('<ii', self.data, body)
        if size_x <= 0 or size_y <= 0 or size_x * size_y > MAX_CELLS:
            raise self.error(body, f'GRIDMAP of {size_x} x {size_y} cells')
        count = size_x * size_y
        (resolution,) = struct.unpack_from('<f', self.data, body + 8)
        cell_type, first = '<f4', body + 12
        if end - body == 16 + 8 * count or not _plausible(resolution):
            # A fork of CARMEN writes doubles (with the float layout's size on some versions).
            if len(self.data) - body >= 16 + 8 * count and _plausible(struct.unpack_from('<d', self.data, body + 8)[0]):
                (resolution,) = struct.unpack_from('<d', self.data, body + 8)
                cell_type, first = '<f8', body + 16
                self.offset = max(self.offset, body + 16 + 8 * count)
                self.notes.append('GRIDMAP cells as 8-byte doubles (a fork of CARMEN writes them so)')
        if not _plausible(resolution):
            raise self.error(body + 8, f'GRIDMAP resolution {resolution!r} m is not a cell size')
        if cell_type == '<f4':
            resolution = _single(resolution)
        width = np.dtype(cell_type).itemsize
        if first + width * count > len(self.data):
            raise self.error(first, f'GRIDMAP cells cut short: {count} cells need {width * count} bytes, '
                                    f'{len(self.data) - first} are left')
        values = np.frombuffer(self.data, dtype=cell_type, count=count, offset=first).astype(np.float64)
        if not np.isfinite(values).all():
            raise self.error(first, 'GRIDMAP cells that are not numbers')
        probability = values.reshape(size_x, size_y).T          # [y, x]: row 0 at y = 0
        return GridMap(_cells(probability), float(resolution), (0.0, 0.0, 0.0), self.path)

    def _places(self, body: int, end: int) -> dict[str, Place]:
        for number in ('<f', '<d'):          # CARMEN writes floats; a fork doubles: the one that fits
            try:
                places, used = self._place_list(body, end, number)
            except struct.error:
                continue
            if used == end:
                return places
        raise self.error(body, 'PLACES chunk whose places do not fill it (as floats or doubles)')

    def _place_list(self, body: int, end: int, number: str) -> tuple[dict[str, Place], int]:
        (count,) = struct.unpack_from('<i', self.data, body)
        if not 0 <= count <= 100_000:
            raise struct.error('count')
        offset, places = body + 4, {}
        size = struct.calcsize(number)
        for _ in range(count):
            if offset + 24 > end:
                raise struct.error('short')
            (kind,) = struct.unpack_from('<i', self.data, offset)
            name = self.data[offset + 4:offset + 24].split(b'\0')[0].decode('latin-1').strip()
            offset += 24
            numbers = {0: 2, 1: 3, 2: 6}.get(kind)
            if numbers is None or offset + numbers * size > end:
                raise struct.error('type')
            values = struct.unpack_from('<' + number[1] * numbers, self.data, offset)
            if number == '<f':
                values = tuple(_single(v) for v in values)
            offset += numbers * size
            if not all(math.isfinite(v) for v in values):
                raise struct.error('not finite')
            if name in places:
                self.notes.append(f'a second place named {name!r} skipped')
                continue
            places[name] = Place(values[0], values[1], values[2] if numbers > 2 else 0.0)
        return places, offset

    def _offlimits(self, body: int, end: int, resolution: float) -> tuple[Polygon, ...]:
        polygons: list[Polygon] = []
        offset = body
        try:
            for kind, ints in (('point', 2), ('line', 4), ('rectangle', 4)):
                (count,) = struct.unpack_from('<i', self.data, offset)
                offset += 4
                if count < 0 or offset + count * ints * 4 > end:
                    raise self.error(offset - 4, f'OFFLIMITS count {count} does not fit its chunk')
                for _ in range(count):
                    values = struct.unpack_from('<' + 'i' * ints, self.data, offset)
                    offset += ints * 4
                    polygons.append(_offlimit_polygon(kind, values, resolution))
        except struct.error as error:
            raise self.error(offset, 'OFFLIMITS chunk cut short') from error
        return tuple(polygons)


def _single(value: float) -> float:
    """A 4-byte float as the decimal it was written from (0.05, not 0.05000000074505806)."""
    return float(f'{value:.7g}')


def _plausible(resolution: float) -> bool:
    return math.isfinite(resolution) and 1e-4 <= resolution <= 100.0


def _cells(probability: np.ndarray) -> np.ndarray:
    """nav_msgs/OccupancyGrid's cells of occupancy probabilities (negative: unknown)."""
    cells = np.full(probability.shape, -1, dtype=np.int8)
    known = probability >= 0.0
    cells[known & (probability <= OCCUPIED_PROBABILITY)] = 0
    cells[known & (probability > OCCUPIED_PROBABILITY)] = 100
    return cells


def _offlimit_polygon(kind: str, values: tuple[int, ...], resolution: float) -> Polygon:
    """The cells an off-limits point, line or rectangle covers, as a polygon in metres."""
    if kind == 'point':
        x, y = values
        return _box(x, y, x + 1, y + 1, resolution)
    x1, y1, x2, y2 = values
    if kind == 'rectangle' or (x1, y1) == (x2, y2):
        return _box(min(x1, x2), min(y1, y2), max(x1, x2) + 1, max(y1, y2) + 1, resolution)
    # A line: the band one cell wide along it, from the first cell's far side to the last's.
    ax, ay, bx, by = ((v + 0.5) * resolution for v in (x1, y1, x2, y2))
    length = math.hypot(bx - ax, by - ay)
    ux, uy = (bx - ax) / length * resolution / 2, (by - ay) / length * resolution / 2
    return ((ax - ux + uy, ay - uy - ux), (bx + ux + uy, by + uy - ux),
            (bx + ux - uy, by + uy + ux), (ax - ux - uy, ay - uy + ux))


def _box(x1: float, y1: float, x2: float, y2: float, resolution: float) -> Polygon:
    return ((x1 * resolution, y1 * resolution), (x2 * resolution, y1 * resolution),
            (x2 * resolution, y2 * resolution), (x1 * resolution, y2 * resolution))


def _beesoft(path: str, data: bytes) -> CarmenMap:
    text = data.decode('latin-1')
    lines = text.splitlines()
    resolution_cm = None
    for number, line in enumerate(lines, start=1):
        if line.startswith('robot_specifications->resolution'):
            try:
                resolution_cm = float(line.split()[1])
            except (IndexError, ValueError) as error:
                raise MapError(path, number, f'resolution {line!r} is not a number') from error
        if line.startswith('global_map[0]'):
            break
    else:
        raise MapError(path, None, 'a BeeSoft map without its global_map[0]: line')
    fields = line.split()
    try:
        size_y, size_x = int(fields[1]), int(fields[2])
    except (IndexError, ValueError) as error:
        raise MapError(path, number, f'{line!r}: need global_map[0]: SIZE_Y SIZE_X') from error
    if resolution_cm is None or not _plausible(resolution_cm / 100.0):
        raise MapError(path, None, f'no usable robot_specifications->resolution (cm): {resolution_cm}')
    if size_x <= 0 or size_y <= 0 or size_x * size_y > MAX_CELLS:
        raise MapError(path, number, f'a map of {size_x} x {size_y} cells')
    words = '\n'.join(lines[number:]).split()
    if len(words) < size_x * size_y:
        raise MapError(path, len(lines), f'cells cut short: {len(words)} of {size_x * size_y}')
    try:
        free = np.array(words[:size_x * size_y], dtype=np.float64)
    except ValueError as error:
        raise MapError(path, None, f'a cell that is not a number: {error}') from error
    probability = np.where(free < 0.0, -1.0, 1.0 - free).reshape(size_x, size_y).T
    notes = ('BeeSoft map: autoshifted offsets ignored, the map starts at 0, 0',) if 'autoshifted' in text else ()
    return CarmenMap(GridMap(_cells(probability), resolution_cm / 100.0, (0.0, 0.0, 0.0), path), {}, (), 'beesoft',
                     notes)
