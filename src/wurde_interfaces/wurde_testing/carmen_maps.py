"""CARMEN map files written byte for byte as CARMEN's map_io writes them, for tests.

:func:`carmen_map_bytes` lays out a ``.map`` file as map_io's ``carmen_map_write_all`` does (the
comment header, ``CARMENMAPFILEv020``, a CREATOR chunk, GRIDMAP, PLACES and OFFLIMITS chunks with
4-byte floats and little-endian int32s); :func:`beesoft_map_text` a BeeSoft (Rhino) text map.
The reader under test is :mod:`wurde_idl.carmen_map`; nothing here is shared with it.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import numpy as np

__all__ = ['beesoft_map_text', 'carmen_map_bytes', 'chunk']

#: (type, name, numbers): type 0 a position (x, y), 1 a pose (x, y, theta), 2 a localization
#: start (x, y, theta, x_std, y_std, theta_std).
PlaceSpec = tuple[int, str, Sequence[float]]


def chunk(kind: int, description: str, data: bytes, name: str | None = None) -> bytes:
    """One chunk: type byte (bit 7 when named), int32 size, 10-character description, name, data.

    :param kind: the chunk type (1 GRIDMAP, 2 OFFLIMITS, 4 PLACES, 32 CREATOR, ...).
    :param description: padded or cut to 10 ASCII characters.
    :param data: the chunk's data.
    :param name: the chunk's name (written with a NUL, bit 7 set); None: an unnamed chunk.
    """
    body = description.ljust(10).encode('ascii')[:10]
    if name is not None:
        body += name.encode('ascii') + b'\0'
        kind |= 0x80
    body += data
    return bytes([kind]) + struct.pack('<i', len(body)) + body


def carmen_map_bytes(probability: np.ndarray, resolution: float, *, places: Sequence[PlaceSpec] = (),
                     points: Sequence[tuple[int, int]] = (), lines: Sequence[tuple[int, int, int, int]] = (),
                     rectangles: Sequence[tuple[int, int, int, int]] = (), cell_bytes: int = 4,
                     grid_name: str | None = None, creator_type: int = 32, extra: bytes = b'') -> bytes:
    """The bytes of a CARMEN map file.

    :param probability: ``probability[x, y]``, the occupied probability of each cell, -1 unknown.
    :param resolution: m per cell.
    :param places: the place list; empty: no PLACES chunk.
    :param points: off-limits cells ``(x, y)``.
    :param lines: off-limits lines ``(x1, y1, x2, y2)`` in cells.
    :param rectangles: off-limits rectangles ``(x1, y1, x2, y2)`` in cells.
    :param cell_bytes: 4 (CARMEN's floats) or 8 (the resolution and cells as doubles, as a fork of
        CARMEN writes them).
    :param grid_name: the GRIDMAP chunk's name; None: unnamed.
    :param creator_type: the CREATOR chunk's type; 0 is CARMEN's old maps' id.
    :param extra: chunks written after the grid, as they are.
    """
    size_x, size_y = probability.shape
    out = (b'#####################################################\n#\n'
           b'# Carnegie Mellon Robot Toolkit (CARMEN) map file\n#\n'
           b'# Map size      : %d x %d\n# Resolution    : %.1f\n#\n'
           b'#####################################################\n' % (size_x, size_y, resolution))
    out += b'CARMENMAPFILEv020'
    creator = b'tester'.ljust(10) + struct.pack('<q', 0) + b'test'.ljust(80) + b'a test map'.ljust(80)
    out += chunk(creator_type, 'CREATOR', creator)
    number = '<f' if cell_bytes == 4 else '<d'
    grid = struct.pack('<ii', size_x, size_y) + struct.pack(number, resolution)
    grid += np.asarray(probability, dtype='<f4' if cell_bytes == 4 else '<f8').tobytes()
    out += chunk(1, 'GRIDMAP', grid, grid_name)
    out += extra
    if places:
        data = struct.pack('<i', len(places))
        for kind, name, numbers in places:
            data += struct.pack('<i', kind) + name.encode('ascii').ljust(20)
            data += struct.pack('<' + number[1] * len(numbers), *numbers)
        out += chunk(4, 'PLACES', data)
    if points or lines or rectangles:
        data = struct.pack('<i', len(points)) + b''.join(struct.pack('<ii', *p) for p in points)
        data += struct.pack('<i', len(lines)) + b''.join(struct.pack('<iiii', *v) for v in lines)
        data += struct.pack('<i', len(rectangles)) + b''.join(struct.pack('<iiii', *v) for v in rectangles)
        out += chunk(2, 'OFFLIMITS', data)
    return out


def beesoft_map_text(probability: np.ndarray, resolution_cm: float) -> str:
    """A BeeSoft (Rhino) text map: each cell as the probability that it is free (``1 - p``), -1
    unknown.

    :param probability: ``probability[x, y]``, the occupied probability of each cell, -1 unknown.
    :param resolution_cm: cm per cell.
    """
    size_x, size_y = probability.shape
    lines = [f'robot_specifications->global_mapsize_x  {size_y * resolution_cm:g}',
             f'robot_specifications->global_mapsize_y  {size_x * resolution_cm:g}',
             f'robot_specifications->resolution {resolution_cm:g}',
             'robot_specifications->autoshifted_x 0', 'robot_specifications->autoshifted_y 0', '',
             f'global_map[0]: {size_y} {size_x}']
    free = np.where(probability < 0, -1.0, 1.0 - probability)
    lines += [' '.join(f'{v:.3f}' for v in row) for row in free]
    return '\n'.join(lines) + '\n'
