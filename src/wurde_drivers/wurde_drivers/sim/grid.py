"""Occupancy grids of the simulated world: rasterising walls, recovering walls, PGM+YAML files.

Semantics follow CARMEN's grid maps (programming-with-carmen.txt, section 5.1): each cell holds the
probability that it is occupied, in ``[0, 1]``, or ``-1`` when unknown.  ``data[iy, ix]`` is the
cell whose lower-left corner is ``origin + (ix, iy) * resolution``: row 0 is the lowest ``y``, as
in ROS's ``nav_msgs/OccupancyGrid``.

Files are the ROS ``map_server`` format, so ROS users can open them: a YAML file (``image``,
``resolution``, ``origin``, ``negate``, ``occupied_thresh``, ``free_thresh``, ``mode``) and an 8-bit
image (PGM) whose top row is the highest ``y``.  :meth:`OccupancyGrid.save` writes what ROS 1's
``map_saver`` writes: ``trinary`` mode, occupied (p >= 0.65) black 0, free (p <= 0.196) 254,
anything else unknown 205; so a grid of 0, 1 and -1 reads back exactly, and probabilities in
between are thresholded.  :meth:`OccupancyGrid.load` reads ``trinary``, ``scale`` and ``raw``.
"""

from __future__ import annotations

import math
import os
import pathlib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import MapError
from .world import World

__all__ = ['FREE', 'OCCUPIED', 'UNKNOWN', 'OccupancyGrid', 'walls_from_grid']

FREE = 0.0
OCCUPIED = 1.0
UNKNOWN = -1.0

# ROS 1 map_saver's thresholds and pixel values (trinary mode).
_OCCUPIED_THRESH = 0.65
_FREE_THRESH = 0.196
_PIXEL_OCCUPIED, _PIXEL_FREE, _PIXEL_UNKNOWN = 0, 254, 205


@dataclass(eq=False)
class OccupancyGrid:
    """Probabilities of occupancy on a regular grid.

    :param data: ``(height, width)`` float32: occupied probability in ``[0, 1]`` or -1 unknown.
    :param resolution: metres per cell.
    :param origin: ``(x, y)`` in metres of the lower-left corner of cell ``(0, 0)``.
    """

    data: NDArray[np.float32]
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        self.data = np.asarray(self.data, dtype=np.float32)
        if self.data.ndim != 2 or 0 in self.data.shape:
            raise ValueError(f'grid data must be a non-empty 2D array, not {self.data.shape}')
        if not (math.isfinite(self.resolution) and self.resolution > 0):
            raise ValueError(f'resolution must be positive, not {self.resolution}')
        self.origin = (float(self.origin[0]), float(self.origin[1]))

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    def cells(self, points: ArrayLike) -> tuple[NDArray, NDArray]:
        """``(ix, iy)`` integer cell indices of ``(N, 2)`` points (not clipped to the grid)."""
        xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        ix = np.floor((xy[:, 0] - self.origin[0]) / self.resolution).astype(np.int64)
        iy = np.floor((xy[:, 1] - self.origin[1]) / self.resolution).astype(np.int64)
        return ix, iy

    def centers(self, ix: ArrayLike, iy: ArrayLike) -> NDArray:
        """``(N, 2)`` world coordinates of the centres of cells ``(ix, iy)``."""
        x = self.origin[0] + (np.asarray(ix, dtype=np.float64) + 0.5) * self.resolution
        y = self.origin[1] + (np.asarray(iy, dtype=np.float64) + 0.5) * self.resolution
        return np.stack([np.atleast_1d(x), np.atleast_1d(y)], axis=1)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, OccupancyGrid):
            return NotImplemented
        return (self.resolution == other.resolution and self.origin == other.origin
                and np.array_equal(self.data, other.data))

    __hash__ = None  # type: ignore[assignment]

    # -- world <-> grid --------------------------------------------------------------------------

    @classmethod
    def from_world(cls, world: World, resolution: float, *,
                   offlimits: bool = False) -> OccupancyGrid:
        """Rasterise ``world`` over its bounds: every cell a wall passes through is occupied.

        :param offlimits: also mark cells whose centre lies in an off-limits region as occupied
            (what a planner's map wants; the sensors' map does not).
        """
        if not (math.isfinite(resolution) and resolution > 0):
            raise ValueError(f'resolution must be positive, not {resolution}')
        box = world.bounds
        width = int(math.floor((box.xmax - box.xmin) / resolution)) + 1
        height = int(math.floor((box.ymax - box.ymin) / resolution)) + 1
        grid = cls(np.zeros((height, width), dtype=np.float32), resolution, (box.xmin, box.ymin))
        for x1, y1, x2, y2 in world.walls:
            ix, iy = grid._segment_cells(x1, y1, x2, y2)
            inside = (ix >= 0) & (ix < width) & (iy >= 0) & (iy < height)
            grid.data[iy[inside], ix[inside]] = OCCUPIED
        if offlimits and world.offlimits:
            iy, ix = np.mgrid[0:height, 0:width]
            mask = world.off_limits_mask(grid.centers(ix.ravel(), iy.ravel()))
            grid.data[mask.reshape(height, width)] = OCCUPIED
        return grid

    def _segment_cells(self, x1: float, y1: float, x2: float, y2: float) -> tuple[NDArray, NDArray]:
        """Every cell the segment passes through (exact: split where it crosses grid lines)."""
        ax, ay = (x1 - self.origin[0]) / self.resolution, (y1 - self.origin[1]) / self.resolution
        bx, by = (x2 - self.origin[0]) / self.resolution, (y2 - self.origin[1]) / self.resolution
        cuts = [np.array([0.0, 1.0])]
        for a, b in ((ax, bx), (ay, by)):
            if a != b:
                lines = np.arange(math.ceil(min(a, b)), math.floor(max(a, b)) + 1, dtype=np.float64)
                cuts.append((lines - a) / (b - a))
        t = np.unique(np.clip(np.concatenate(cuts), 0.0, 1.0))
        samples = np.concatenate([t, 0.5 * (t[:-1] + t[1:])])
        ix = np.floor(ax + samples * (bx - ax)).astype(np.int64)
        iy = np.floor(ay + samples * (by - ay)).astype(np.int64)
        return ix, iy

    def to_world(self, *, threshold: float = 0.5, name: str = '') -> World:
        """A world of the :func:`walls_from_grid` of this grid, bounded by the grid's extent."""
        bounds = (self.origin[0], self.origin[1], self.origin[0] + self.width * self.resolution,
                  self.origin[1] + self.height * self.resolution)
        return World(walls_from_grid(self, threshold=threshold), bounds=bounds, name=name)

    # -- files -----------------------------------------------------------------------------------

    def save(self, yaml_path: str | os.PathLike[str]) -> pathlib.Path:
        """Write ``<name>.yaml`` and ``<name>.pgm`` beside it (ROS map_server, trinary).

        :returns: the path of the image.
        """
        import cv2  # lazy: only the file functions need OpenCV

        yaml_file = pathlib.Path(yaml_path)
        image_file = yaml_file.with_suffix('.pgm')
        pixels = np.full(self.data.shape, _PIXEL_UNKNOWN, dtype=np.uint8)
        pixels[self.data >= _OCCUPIED_THRESH] = _PIXEL_OCCUPIED
        pixels[(self.data >= 0.0) & (self.data <= _FREE_THRESH)] = _PIXEL_FREE
        if not cv2.imwrite(str(image_file), np.flipud(pixels)):
            raise OSError(f'cannot write {image_file}')
        yaml_file.write_text(
            f'image: {image_file.name}\n'
            f'mode: trinary\n'
            f'resolution: {self.resolution!r}\n'
            f'origin: [{self.origin[0]!r}, {self.origin[1]!r}, 0.0]\n'
            f'negate: 0\n'
            f'occupied_thresh: {_OCCUPIED_THRESH}\n'
            f'free_thresh: {_FREE_THRESH}\n')
        return image_file

    @classmethod
    def load(cls, yaml_path: str | os.PathLike[str]) -> OccupancyGrid:
        """Read a ROS map_server map (YAML and image).

        :raises MapError: naming the YAML file (and line) for a missing or bad key, an image that
            cannot be read, a rotated origin or an unknown mode.
        """
        import cv2

        path = os.fspath(yaml_path)
        keys = _yaml_mapping(path)

        def value(key: str, default: Any = None) -> tuple[Any, int | None]:
            if key not in keys:
                if default is None:
                    raise MapError(path, None, f'missing key {key!r}')
                return default, None
            return keys[key]

        def number(key: str, default: float | None = None) -> float:
            raw, line = value(key, default)
            if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
                raise MapError(path, line, f'{key} must be a finite number, not {raw!r}')
            return float(raw)

        resolution = number('resolution')
        if resolution <= 0:
            raise MapError(path, keys['resolution'][1], 'resolution must be positive')
        origin, line = value('origin')
        if (not isinstance(origin, list) or len(origin) != 3
                or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in origin)):
            raise MapError(path, line, f'origin must be [x, y, yaw], not {origin!r}')
        if origin[2] != 0:
            raise MapError(path, line, 'a rotated map (origin yaw != 0) is not supported')
        negate = number('negate', 0)
        occupied_thresh = number('occupied_thresh', _OCCUPIED_THRESH)
        free_thresh = number('free_thresh', _FREE_THRESH)
        mode, mode_line = value('mode', 'trinary')
        if mode not in ('trinary', 'scale', 'raw'):
            raise MapError(path, mode_line, f'mode must be trinary, scale or raw, not {mode!r}')
        image_name, image_line = value('image')
        image_file = pathlib.Path(path).parent / str(image_name)
        pixels = cv2.imread(str(image_file), cv2.IMREAD_UNCHANGED)
        if pixels is None or pixels.dtype != np.uint8:
            raise MapError(path, image_line, f'cannot read {image_file} as an 8-bit image')
        if pixels.ndim == 3:  # ROS averages the colour channels (an alpha channel is ignored)
            pixels = pixels[:, :, :3].mean(axis=2)
        pixels = np.flipud(pixels).astype(np.float64)
        if mode == 'raw':
            data = np.where(pixels <= 100, pixels / 100.0, UNKNOWN)
        else:
            occupancy = pixels / 255.0 if negate else (255.0 - pixels) / 255.0
            middle = UNKNOWN if mode == 'trinary' else \
                (occupancy - free_thresh) / (occupied_thresh - free_thresh)
            data = np.where(occupancy > occupied_thresh, OCCUPIED,
                            np.where(occupancy < free_thresh, FREE, middle))
        return cls(data.astype(np.float32), resolution, (float(origin[0]), float(origin[1])))


def _yaml_mapping(path: str) -> dict[str, tuple[Any, int]]:
    """The top-level mapping of a YAML file: key -> (value, line), errors with file and line."""
    import yaml

    try:
        text = pathlib.Path(path).read_text()
    except OSError as error:
        raise MapError(path, None, f'cannot read: {error.strerror}') from error
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
        content = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        raise MapError(path, mark.line + 1 if mark else None, f'not valid YAML: {error}') from error
    if not isinstance(content, dict) or not isinstance(node, yaml.MappingNode):
        raise MapError(path, 1, 'a map YAML file must be a mapping (image: ..., resolution: ...)')
    lines = {str(key.value): key.start_mark.line + 1 for key, _ in node.value
             if isinstance(key, yaml.ScalarNode)}
    return {str(key): (item, lines.get(str(key), 0)) for key, item in content.items()}


def walls_from_grid(grid: OccupancyGrid, *, threshold: float = 0.5) -> NDArray:
    """Walls ``(N, 4)`` recovered from the occupied cells (``p >= threshold``) of ``grid``.

    Runs of two or more occupied cells in a row become one horizontal segment through their
    centres, runs in a column one vertical segment; an occupied cell in neither becomes a segment
    one cell long across its centre.  Accuracy: every occupied cell's centre lies on a recovered
    wall and every recovered wall lies in occupied cells, so for a grid rasterised from a world the
    recovered walls are within one cell diagonal (``resolution * sqrt(2)``) of the original ones,
    and axis-aligned walls within half a cell.  Oblique walls come back as staircases.
    """
    occupied = np.asarray(grid.data) >= threshold
    # In cell units (cell centres at i + 0.5), as (x1, y1, x2, y2) = (ix, iy, ix, iy).
    pieces = [_runs(occupied), _runs(occupied.T)[:, [1, 0, 3, 2]]]
    padded = np.pad(occupied, 1)
    neighbours = (padded[1:-1, :-2] | padded[1:-1, 2:] | padded[:-2, 1:-1] | padded[2:, 1:-1])
    iy, ix = np.nonzero(occupied & ~neighbours)
    pieces.append(np.column_stack([ix, iy + 0.5, ix + 1.0, iy + 0.5]))
    cells = np.vstack(pieces)
    ox, oy = grid.origin
    return cells * grid.resolution + np.array([ox, oy, ox, oy])


def _runs(occupied: NDArray) -> NDArray:
    """``(along1, row, along2, row)`` in cell units: the centres of the first and last cell of each
    run of two or more occupied cells along the rows of ``occupied``."""
    padded = np.pad(occupied.astype(np.int8), ((0, 0), (1, 1)))
    change = np.diff(padded, axis=1)
    rows, starts = np.nonzero(change == 1)
    _, ends = np.nonzero(change == -1)  # row-major order pairs each start with its own end
    long = ends - starts >= 2
    rows, starts, last = rows[long], starts[long], ends[long] - 1
    return np.column_stack([starts, rows, last, rows]).astype(np.float64) + 0.5
