"""Occupancy grids as ROS's map_server stores them: a YAML file and the PGM image it names.

The format (nav2_map_server / map_server's documentation): the YAML holds ``image`` (a path,
relative to the YAML's directory), ``resolution`` (m per pixel), ``origin`` (``[x, y, yaw]``, the
pose of the image's lower-left pixel), ``negate``, ``occupied_thresh``, ``free_thresh`` and
``mode`` (``trinary``, ``scale`` or ``raw``).  A pixel's occupancy is ``(255 - value) / 255``
(``value / 255`` when negated); above ``occupied_thresh`` it is occupied, below ``free_thresh``
free, else unknown.  The image's first row is the map's top (largest y).

Cells here are nav_msgs/OccupancyGrid's: ``cells[row, col]``, row 0 at the origin's y, columns
along +x; 100 occupied, 0 free, -1 unknown.  :func:`save_grid_map` writes a trinary map
(0 black: occupied, 254 white: free, 205 grey: unknown; thresholds 0.65 and 0.196, ROS's map_saver's,
which read the grey back as unknown), as map_saver does; :func:`load_grid_map`
reads what map_server reads in trinary and scale modes, PGM images only (binary P5, 8 or 16
bits, and plain P2), and refuses anything else with the file, the line and the reason.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pathlib
import tempfile
from collections.abc import Callable

import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray

from .errors import MapError

__all__ = ['GridMap', 'load_grid_map', 'save_grid_map']

OCCUPIED_PIXEL, FREE_PIXEL, UNKNOWN_PIXEL = 0, 254, 205
#: YAML keys map_server knows.
_KEYS = {'image', 'resolution', 'origin', 'negate', 'occupied_thresh', 'free_thresh', 'mode'}


@dataclasses.dataclass(frozen=True)
class GridMap:
    """A map_server map: ``cells`` as nav_msgs/OccupancyGrid's (see the module's description)."""

    cells: NDArray
    resolution: float
    origin: tuple[float, float, float]
    image: str = ''


def save_grid_map(path: str | os.PathLike[str], cells: ArrayLike, *, origin: tuple[float, ...],
                  resolution: float, occupied_thresh: float = 0.65, free_thresh: float = 0.196) -> None:
    """Write ``path`` (the YAML) and the PGM beside it (same name, ``.pgm``), each atomically,
    as a trinary map: 0 free, 50 and above occupied, anything else unknown.

    :param path: the YAML file.
    :param cells: ``cells[row, col]`` as nav_msgs/OccupancyGrid's (row 0 at the origin's y).
    :param origin: ``(x, y)`` or ``(x, y, yaw)`` of cell (0, 0)'s lower-left corner.
    :param resolution: m per cell.
    :param occupied_thresh: written into the YAML for the readers.
    :param free_thresh: written into the YAML for the readers.
    :raises ValueError: for cells that are not a non-empty 2-D array.
    """
    grid = np.asarray(cells)
    if grid.ndim != 2 or grid.size == 0:
        raise ValueError(f'cells must be a non-empty 2-D array, not shape {grid.shape}')
    yaml_path = pathlib.Path(path)
    image_path = yaml_path.with_suffix('.pgm')
    pixels = np.full(grid.shape, UNKNOWN_PIXEL, dtype=np.uint8)
    pixels[grid == 0] = FREE_PIXEL
    pixels[grid >= 50] = OCCUPIED_PIXEL
    header = f'P5\n# wurde_idl.gridmap\n{grid.shape[1]} {grid.shape[0]}\n255\n'.encode('ascii')
    x, y, *rest = (float(v) for v in origin)
    text = (f'image: {image_path.name}\nmode: trinary\nresolution: {float(resolution)!r}\n'
            f'origin: [{x!r}, {y!r}, {float(rest[0]) if rest else 0.0!r}]\nnegate: 0\n'
            f'occupied_thresh: {occupied_thresh!r}\nfree_thresh: {free_thresh!r}\n')
    _write(image_path, header + pixels[::-1].tobytes())
    _write(yaml_path, text.encode('ascii'))


def _write(path: pathlib.Path, data: bytes) -> None:
    handle, temporary = tempfile.mkstemp(prefix='.map-', dir=path.parent)
    try:
        with os.fdopen(handle, 'wb') as file:
            file.write(data)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def load_grid_map(path: str | os.PathLike[str]) -> GridMap:
    """Read a map_server YAML and its image.

    :param path: the YAML file (its ``image`` is relative to its directory).
    :raises MapError: naming the file, the line (where there is one) and the reason.
    """
    path = os.fspath(path)
    try:
        with open(path, 'rb') as file:
            raw = file.read(1 << 20)
    except OSError as error:
        raise MapError(path, None, f'cannot be read: {error.strerror or error}') from error
    try:
        meta = yaml.safe_load(raw)
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        raise MapError(path, mark.line + 1 if mark else None,
                       f'not YAML: {getattr(error, "problem", error)}') from error
    if not isinstance(meta, dict):
        raise MapError(path, None, 'a map YAML must be a mapping of keys (image, resolution, origin, ...)')
    lines = _key_lines(raw)

    def fail(key: str, reason: str) -> MapError:
        return MapError(path, lines.get(key), reason)

    unknown = sorted(set(map(str, meta)) - _KEYS)
    if unknown:
        raise fail(unknown[0], f'unknown key {unknown[0]!r} (map_server knows {", ".join(sorted(_KEYS))})')
    for key in ('image', 'resolution', 'origin'):
        if key not in meta:
            raise MapError(path, None, f'missing key {key!r}')
    resolution = _number(meta['resolution'], 'resolution', fail)
    if not resolution > 0:
        raise fail('resolution', f'resolution must be positive, not {resolution}')
    origin = meta['origin']
    if not isinstance(origin, list) or len(origin) != 3:
        raise fail('origin', 'origin must be a list [x, y, yaw]')
    origin_values = tuple(_number(v, 'origin', fail) for v in origin)
    occupied = _number(meta.get('occupied_thresh', 0.65), 'occupied_thresh', fail)
    free = _number(meta.get('free_thresh', 0.196), 'free_thresh', fail)
    if not 0.0 <= free <= occupied <= 1.0:
        raise fail('free_thresh', f'need 0 <= free_thresh ({free}) <= occupied_thresh ({occupied}) <= 1')
    mode = str(meta.get('mode', 'trinary'))
    if mode not in ('trinary', 'scale'):
        raise fail('mode', f'mode {mode!r}: only trinary and scale are read')
    negate = meta.get('negate', 0)
    if negate not in (0, 1, True, False):
        raise fail('negate', f'negate must be 0 or 1, not {negate!r}')
    image = pathlib.Path(path).parent / str(meta['image'])
    pixels = _read_pgm(image, path, lines.get('image'))
    occupancy = pixels if negate else 1.0 - pixels
    cells = np.full(pixels.shape, -1, dtype=np.int8)
    cells[occupancy > occupied] = 100
    cells[occupancy < free] = 0
    return GridMap(cells[::-1].copy(), resolution, origin_values, str(image))  # type: ignore[arg-type]


def _key_lines(raw: bytes) -> dict[str, int]:
    found = {}
    for number, line in enumerate(raw.decode('utf-8', errors='replace').splitlines(), start=1):
        key = line.split(':', 1)[0].strip()
        if key and not line.startswith((' ', '\t', '#')) and key not in found:
            found[key] = number
    return found


def _number(value: object, key: str, fail: Callable[[str, str], MapError]) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise fail(key, f'{key} must be a finite number, not {value!r}')
    return float(value)


def _read_pgm(image: pathlib.Path, yaml_path: str, line: int | None) -> NDArray:
    """The image's pixels as floats in [0, 1], first row the top of the map."""
    try:
        data = image.read_bytes()
    except OSError as error:
        raise MapError(yaml_path, line, f'image {image}: cannot be read: {error.strerror or error}') from error
    magic = data[:2]
    if magic not in (b'P5', b'P2'):
        raise MapError(str(image), None, 'only PGM images (P5 or P2) are read here; convert it to PGM')
    fields: list[int] = []
    offset = 2
    while len(fields) < 3:
        while offset < len(data) and data[offset:offset + 1].isspace():
            offset += 1
        if data[offset:offset + 1] == b'#':
            offset = data.find(b'\n', offset) + 1 or len(data)
            continue
        start = offset
        while offset < len(data) and not data[offset:offset + 1].isspace():
            offset += 1
        if start == offset:
            raise MapError(str(image), None, 'truncated PGM header')
        try:
            fields.append(int(data[start:offset]))
        except ValueError as error:
            raise MapError(str(image), None, f'bad PGM header field {data[start:offset]!r}') from error
    width, height, maxval = fields
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapError(str(image), None, f'bad PGM size {width}x{height} or maximum {maxval}')
    body = data[offset + 1:]
    count = width * height
    if magic == b'P5':
        dtype = np.dtype('>u2') if maxval > 255 else np.dtype(np.uint8)
        if len(body) < count * dtype.itemsize:
            raise MapError(str(image), None, f'PGM data truncated: {len(body)} bytes for {width}x{height}')
        values = np.frombuffer(body, dtype=dtype, count=count).astype(np.float64)
    else:
        try:
            values = np.array(body.split()[:count], dtype=np.float64)
        except ValueError as error:
            raise MapError(str(image), None, 'PGM (P2) pixel that is not a number') from error
        if len(values) < count:
            raise MapError(str(image), None, f'PGM data truncated: {len(values)} of {count} pixels')
    return (values / maxval).reshape(height, width)
