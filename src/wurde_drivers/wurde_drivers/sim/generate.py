"""Random maps and routes, for benchmarks on maps nobody has seen.

``random_map(seed, kind)`` draws a :class:`~.world.World` of one of :data:`KINDS` (see
:mod:`.layouts`): ``rooms`` (rows of rooms off corridors, doors 0.9 to 1.3 m), ``maze`` (a braided
maze of corridors on a jittered lattice) or ``outdoor`` (a fenced area with scattered, turned and
non-rectangular buildings).  Every map has walls at varied angles, furniture-like small
obstacles, a place ``start`` more than 1 m from any wall, and free space that stays connected
for a robot of radius 0.35 m.  The same seed, kind and size give the same map.
``random_route(world, seed, length_m)`` (:mod:`.route`) gives waypoints from ``start`` whose
straight legs keep clear of walls and off-limits regions.  No rclpy here.

Command line (the route is printed in the format of ``tour -w``)::

    python -m wurde_drivers.sim.generate --seed 7 --kind rooms -o rooms-7.xml --route-length 200
    tour -c sim-config.xml -w "$(python -m wurde_drivers.sim.generate ... --route-length 200)"
"""

from __future__ import annotations

import argparse
import random
import sys

from .layouts import LAYOUTS
from .mapfile import save_map
from .route import CLEARANCE, random_route, route_length
from .world import World

__all__ = ['KINDS', 'SIZES', 'format_route', 'main', 'random_map', 'random_route']

#: The kinds of map :func:`random_map` draws.
KINDS = tuple(LAYOUTS)
#: Kind -> the range (metres) of the longer side drawn when no size is given.
SIZES = {'rooms': (15.0, 50.0), 'maze': (10.0, 40.0), 'outdoor': (30.0, 80.0)}
#: Sizes :func:`random_map` accepts, metres.
SIZE_RANGE = (10.0, 100.0)


def random_map(seed: int, kind: str = 'rooms', *, size: float | None = None) -> World:
    """A random map of ``kind``, named ``<kind>-<seed>``.

    :param seed: any integer; the same seed (with the same kind and size) gives the same map.
    :param kind: one of :data:`KINDS`.
    :param size: the longer side in metres (10 to 100); by default drawn from :data:`SIZES`.
    :raises ValueError: an unknown kind or a size out of range.
    """
    if kind not in LAYOUTS:
        raise ValueError(f'unknown kind {kind!r}; known: {", ".join(KINDS)}')
    rng = random.Random(f'{kind}/{seed}')
    if size is None:
        size = rng.uniform(*SIZES[kind])
    elif not SIZE_RANGE[0] <= size <= SIZE_RANGE[1]:
        raise ValueError(f'size must be {SIZE_RANGE[0]:g} to {SIZE_RANGE[1]:g} m, got {size}')
    layout = LAYOUTS[kind](rng, float(size))
    return layout.sketch.world(f'{kind}-{seed}', angle=layout.angle)


def format_route(route: list[tuple[float, float]]) -> str:
    """``"x,y x,y ..."``: the waypoints as ``tour -w`` reads them (every number exact)."""
    return ' '.join(f'{x!r},{y!r}' for x, y in route)


def main(argv: list[str] | None = None) -> int:
    """Write a random map; with ``--route-length``, print a route through it for ``tour -w``."""
    parser = argparse.ArgumentParser(
        prog='python -m wurde_drivers.sim.generate',
        description='Write a random map (config/maps/README.md format); optionally print a route '
                    'through it in the format of tour -w (the waypoints after start).')
    parser.add_argument('--seed', type=int, required=True)
    parser.add_argument('--kind', choices=KINDS, default='rooms')
    parser.add_argument('--size', type=float, help='longer side in metres (10 to 100)')
    parser.add_argument('-o', '--output', required=True, help='the map file to write')
    parser.add_argument('--route-length', type=float, metavar='M',
                        help='print a route of at least M metres from start')
    parser.add_argument('--clearance', type=float, default=CLEARANCE,
                        help=f'metres each leg keeps from walls (default {CLEARANCE:g})')
    args = parser.parse_args(argv)
    try:
        world = random_map(args.seed, args.kind, size=args.size)
        save_map(world, args.output)
        print(f'generate: {world!r} -> {args.output}', file=sys.stderr)
        if args.route_length is not None:
            route = random_route(world, args.seed, args.route_length, clearance=args.clearance)
            print(format_route(route[1:]))
            print(f'generate: route of {len(route) - 1} waypoints, {route_length(route):.1f} m',
                  file=sys.stderr)
    except (ValueError, OSError) as error:
        print(f'generate: {error}', file=sys.stderr)
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
