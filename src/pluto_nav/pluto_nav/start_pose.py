"""Where the localModule starts: a pose file, or the map's ``start`` place (Pluto 3: "The starting
pose is read from a file").

The pose file is text, one pose on one line, metres and radians in the map frame::

    # the robot's starting pose: x y theta
    3.0 7.5 0.0

Blank lines and ``#`` comments are ignored; exactly one pose line with three finite numbers is
allowed.  Anything else is refused with the file, the line and the reason
(:class:`wurde_idl.errors.ConfigError`).  Without a pose file the start is the map's place named
``start`` (every shipped and generated map has one, config/maps/README.md); without a map, the
origin.
"""

from __future__ import annotations

import math
import os

from wurde_idl.errors import ConfigError
from wurde_idl.maps import load_map

__all__ = ['read_pose_file', 'start_pose']


def read_pose_file(path: str | os.PathLike[str]) -> tuple[float, float, float]:
    """The pose ``x y theta`` of a pose file.

    :param path: the file: exactly one line ``x y theta`` (metres, radians), ``#`` comments.
    :raises ConfigError: unreadable, no pose, a second pose, or a malformed or non-finite value.
    """
    try:
        with open(path, encoding='utf-8') as stream:
            lines = stream.read().splitlines()
    except OSError as error:
        raise ConfigError(path, None, f'cannot read the pose file: {error.strerror}') from None
    except UnicodeDecodeError:
        raise ConfigError(path, None, 'not a text file') from None
    found: tuple[float, float, float] | None = None
    for number, line in enumerate(lines, start=1):
        text = line.split('#', 1)[0].strip()
        if not text:
            continue
        if found is not None:
            raise ConfigError(path, number, 'a second pose; the file holds exactly one "x y theta"')
        fields = text.split()
        if len(fields) != 3:
            raise ConfigError(path, number, f'expected "x y theta" (3 numbers), got {len(fields)} fields')
        try:
            values = tuple(float(field) for field in fields)
        except ValueError:
            raise ConfigError(path, number, f'not a number in {text!r}') from None
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(path, number, f'not finite: {text!r}')
        found = values  # type: ignore[assignment]
    if found is None:
        raise ConfigError(path, None, 'no pose in the file; expected one line "x y theta"')
    return found


def start_pose(pose_file: str | None, map_file: str | None) -> tuple[float, float, float]:
    """The pose file's pose if given, else the map's ``start`` place, else the origin.

    :param pose_file: the ``-p`` pose file, or None.
    :param map_file: the ``-m`` map (any format :func:`wurde_idl.maps.load_map` reads), or None.
    :raises ConfigError: a bad pose file, or a map with no place ``start``.
    """
    if pose_file:
        return read_pose_file(pose_file)
    if map_file:
        data = load_map(map_file)
        if 'start' not in data.places:
            raise ConfigError(map_file, None, 'the map has no place "start"; give a pose file (-p)')
        x, y, theta = data.places['start']
        return float(x), float(y), float(theta)
    return 0.0, 0.0, 0.0
