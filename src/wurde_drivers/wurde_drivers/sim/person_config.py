"""``<person>`` of sim-config.xml: a moving obstacle's body, walk, speed and pauses, as written.

::

    <person name="ana" points="10,10.3 10,7.5 7.5,7.5 7.5,4" speed="1.2" pause="3"
            mode="back-and-forth" radius="0.25" height="1.7"/>
    <person name="ben" random="6" area="5,6.7 19,8.3" speed="0.8" radius="0.3"/>
    <person name="trolley" points="12.5,4.5 12.5,7.5 16.5,7.5 16.5,10.5" speed="0.6"
            length="0.9" width="0.6" height="1.0"/>

- ``name`` (required, unique): says who in logs and on the truth topic.
- The walk: ``points="x,y x,y ..."`` (metres, map frame: two or more waypoints, scripted) or
  ``random="N"`` (N waypoints drawn from the free space of ``area="xmin,ymin xmax,ymax"``, the
  map's bounds by default, with the config's seed and the person's name: the same on every run
  and in every process); ``mode`` ``loop`` (default: back to the first point and round again)
  or ``back-and-forth``; ``speed`` m/s in (0, 1.5] (default 1.0); ``pause`` seconds standing at
  each waypoint (default 0).  Where a person is at a stamp: :mod:`.walk`.
- The body: ``radius`` (a disc, default 0.25 m when no size is given) or ``length`` and
  ``width`` (a box whose length lies along the walking direction); ``height`` (default 1.75 m)
  must be above every laser's ``mount-z`` and the sonars' height, or the sensors could not see it.

This module reads what needs no map; :mod:`.crowd` draws random walks and refuses a walk whose
body would touch a wall or the robot at its start, both with the file and the ``<person>``'s line.
"""

from __future__ import annotations

import dataclasses
import math

from ..xml_config import Attributes
from .people import Body
from .walk import LOOP, MAX_SPEED, MODES

__all__ = ['PERSON_ATTRIBUTES', 'PersonConfig', 'read_person']

PERSON_ATTRIBUTES = ('name', 'points', 'random', 'area', 'mode', 'speed', 'pause',
                     'radius', 'length', 'width', 'height')
#: Limits of the body (m): people and trolleys, not buildings.
MAX_RADIUS = 1.0
MAX_SIDE = 2.0
MAX_HEIGHT = 3.0
#: Most waypoints a random walk may ask for.
MAX_RANDOM = 50
#: Default disc radius (m) when a person gives no size: a person's shoulders.
DEFAULT_RADIUS = 0.25


@dataclasses.dataclass(frozen=True)
class PersonConfig:
    """One ``<person>`` as written: ``points`` for a scripted walk, or ``random`` waypoints to
    draw in ``area`` (``xmin, ymin, xmax, ymax``; None: the map's bounds)."""

    name: str
    line: int | None
    body: Body
    speed: float = 1.0
    pause: float = 0.0
    mode: str = LOOP
    points: tuple[tuple[float, float], ...] = ()
    random: int = 0
    area: tuple[float, float, float, float] | None = None


def _pairs(a: Attributes, name: str) -> list[tuple[float, float]]:
    """``name="x,y x,y ..."``, every pair checked, errors with the file and line of ``a``."""
    pairs = []
    for text in a.text(name).split():
        parts = text.split(',')
        try:
            x, y = (float(v) for v in parts)
        except ValueError:
            raise a.error(f'{name} of <{a.tag}>: "{text}" is not x,y') from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise a.error(f'{name} of <{a.tag}>: "{text}" is not finite')
        pairs.append((x, y))
    return pairs


def _body(a: Attributes) -> Body:
    height = a.number('height', 1.75, maximum=MAX_HEIGHT)
    if height <= 0.0:
        raise a.error(f'height={height:g} of <person> must be above 0')
    box = [name for name in ('length', 'width') if a.has(name)]
    if box and a.has('radius'):
        raise a.error('a <person> is a disc (radius) or a box (length and width), not both')
    if len(box) == 1:
        raise a.error(f'a box <person> needs both length and width (only {box[0]} given)')
    if box:
        sizes = [a.number(name, maximum=MAX_SIDE) for name in ('length', 'width')]
        if min(sizes) <= 0.0:
            raise a.error('length and width of <person> must be above 0')
        return Body(height=height, length=sizes[0], width=sizes[1])
    radius = a.number('radius', DEFAULT_RADIUS, maximum=MAX_RADIUS)
    if radius <= 0.0:
        raise a.error(f'radius={radius:g} of <person> must be above 0')
    return Body(height=height, radius=radius)


def read_person(a: Attributes) -> PersonConfig:
    """One ``<person>``.

    :param a: its attributes, already checked against :data:`PERSON_ATTRIBUTES`.
    :raises ConfigError: with the file, the line and the reason.
    """
    name = a.text('name')
    speed = a.number('speed', 1.0)
    if not 0.0 < speed <= MAX_SPEED:
        raise a.error(f'speed={speed:g} of <person> "{name}" must be in (0, {MAX_SPEED:g}] m/s')
    pause = a.number('pause', 0.0, minimum=0.0, maximum=3600.0)
    mode = a.choice('mode', MODES, LOOP)
    body = _body(a)
    common = dict(name=name, line=a.line, body=body, speed=speed, pause=pause, mode=mode)
    if a.has('points') == a.has('random'):
        raise a.error(f'<person> "{name}" needs either points (a scripted walk) or random '
                      '(waypoints drawn from free space), and not both')
    if a.has('points'):
        if a.has('area'):
            raise a.error('area of <person> goes with random, not with points')
        points = _pairs(a, 'points')
        if len(points) < 2:
            raise a.error(f'<person> "{name}" needs at least 2 points, got {len(points)}')
        return PersonConfig(**common, points=tuple(points))
    count = a.number('random', integer=True, minimum=2, maximum=MAX_RANDOM)
    area = None
    if a.has('area'):
        corners = _pairs(a, 'area')
        if len(corners) != 2:
            raise a.error(f'area of <person> is two corners "xmin,ymin xmax,ymax", got {len(corners)}')
        (x1, y1), (x2, y2) = corners
        if not (x1 < x2 and y1 < y2):
            raise a.error(f'area of <person> "{name}" is empty: "xmin,ymin xmax,ymax" with xmin < xmax '
                          'and ymin < ymax')
        area = (x1, y1, x2, y2)
    return PersonConfig(**common, random=count, area=area)
