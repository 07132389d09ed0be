"""Benchmark: Pluto's slamModule under the MCP against the simulator's truth (issue 11's SLAM rows).

Per map (the shipped ones and ``--generated`` generated ones; config/pluto's noise: odometry trans
0.05 / rot 0.05 / drift 0.02, laser 0.01 m, DMU rate noise on):

1. the simulated Pluto with localModule and slamModule (``-a``: the thread runs from the start)
   drives a loop under ``tour -L Localization/Pose``: a random route of ``--length`` metres out
   (:func:`wurde_drivers.sim.route.random_route`) and the shortest way back to the start, so the
   SLAM closes the loop on walls it mapped at the beginning.  The Pose (3), which the slamModule
   corrects, is compared with the truth, next to dead reckoning and odometry alone;
2. the MCP stops the modules and the slamModule saves its map as it ends (Pluto 7.2); every mapped
   wall is scored by the farthest point of it from the true walls and by how far its ends lie
   from one true wall (``src/pluto_nav/test/slam_sim.py``);
3. a second run on the same world, with a poseModule loading the saved map (``-m``), drives a new
   ``--relocalize`` metre route: the Pose against the truth shows the map is good to localize in.

Targets (issue 11): Pose RMSE <= 10 cm over a 100 m loop with closure; every mapped wall within
10 cm of the true one; the saved map reloaded and localized against.

Usage: ``make bench-slam`` or ``python bench/nav_slam.py [--length 70] [--generated 3]
[--relocalize 30] [--time-scale 2]`` inside env.sh.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / 'src' / 'pluto_nav' / 'test'))

import nav_run  # noqa: E402
HEADER = ('| map | loop m | route done | Pose RMSE cm | Pose heading RMSE deg | Pose max cm | '
          'odometry alone RMSE cm | walls | wall max cm | walls > 10 cm | ends max cm | '
          'reloaded map: driven m | Pose RMSE cm | Pose max cm | wall s |\n|' + '---|' * 15)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--length', type=float, default=70.0, help='the way out of each loop (m)')
    parser.add_argument('--generated', type=int, default=3, help='generated maps (one per kind, cycling)')
    parser.add_argument('--seed', type=int, default=31, help='first seed of generated maps and routes')
    parser.add_argument('--relocalize', type=float, default=30.0, help='route with the saved map (m)')
    parser.add_argument('--time-scale', type=float, default=2.0, help='simulated seconds per wall second')
    parser.add_argument('--shipped', default='office,corridor-loop,outdoor', help='shipped maps to run')
    args = parser.parse_args()
    work, maps = nav_run.bench_setup('make bench-slam', args.shipped, args.generated, args.seed)
    import numpy as np
    from slam_sim import wall_errors, wall_errors_same_wall
    from wurde_drivers.sim.mapfile import load_map
    from wurde_drivers.sim.route import random_route
    from wurde_idl.mapfile import load_map_data
    print(HEADER, flush=True)
    for i, (name, path) in enumerate(maps):
        world = load_map(path)
        loop = random_route(world, args.seed + 100 + i, args.length, home=True)
        directory = work / f'slam{i}'
        limit = 3 * (args.length * 2) / 0.3 / args.time_scale + 120
        slam = nav_run.run(name, path, loop, directory, estimator='slamModule', seed=args.seed + i,
                           time_scale=args.time_scale, limit_s=limit, estimator_options='-a -f slam-map.xml')
        saved = directory / 'slam-map.xml'
        cells = [f'{slam.driven_m:.0f}', 'yes' if slam.reached else 'NO',
                 f'{slam.pose.position_rmse * 100:.1f}', f'{slam.pose.heading_rmse_deg:.2f}',
                 f'{slam.pose.position_max * 100:.1f}', f'{slam.odometry.position_rmse * 100:.1f}']
        if saved.exists():
            walls = np.asarray(load_map_data(saved).walls, dtype=float).reshape(-1, 4)
            errors, ends = wall_errors(walls, world), wall_errors_same_wall(walls, world)
            cells += [str(len(walls)), f'{errors.max() * 100:.1f}', str(int((errors > 0.10).sum())),
                      f'{ends.max() * 100:.1f}']
            route = random_route(world, args.seed + 300 + i, args.relocalize)
            again = nav_run.run(f'{name} (saved map)', path, route, work / f'reload{i}', estimator='poseModule',
                                seed=args.seed + 50 + i, time_scale=args.time_scale,
                                limit_s=3 * args.relocalize / 0.3 / args.time_scale + 120,
                                estimator_options=f'-m {saved}')
            cells += [f'{again.driven_m:.0f}', f'{again.pose.position_rmse * 100:.1f}',
                      f'{again.pose.position_max * 100:.1f}']
            seconds = slam.seconds + again.seconds
        else:
            cells += ['no map saved'] + ['-'] * 6
            seconds = slam.seconds
        print(f'| {name} | ' + ' | '.join(cells) + f' | {seconds:.0f} |', flush=True)
    print(f'(runs in {work})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
