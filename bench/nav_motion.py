"""Benchmark: the movement chain's goto (cmdFlags 32) and moveto (42) against the simulator's truth.

Issue 12's table.  On the shipped maps and on generated ones (:mod:`wurde_drivers.sim.generate`:
rooms with 0.9-1.3 m doors, mazes with dead ends, outdoor areas), config/pluto's whole robot runs
under the MCP — dummies with odometry noise, localModule, poseModule, drive, avoid, motion (planning
on the map) — and a client sends every command through ``motion/command``, as a user would.  Per
map, ``--pairs`` random goals (free, 0.6 m or more from walls, 2 m or more apart, each reachable
from the one before on the map) are visited in turn, once by moveto and once (the MCP started
again, the robot back at the start) by the simple goto.  Per pair: success (the command's own
success code and the truth within 0.4 m of the goal), collision (a bumper pressed, or the truth
nearer a wall than the robot's radius), time, and the truth's path over the shortest path for the
robot's disc on the map (from where the robot really was).  Mode ``rays`` is moveto too, with the
motionModule started with ``-R``: Pluto's own ray following (6.3) on the same map and goals.

Targets (issue 12): moveto reaches 100 % of reachable goals with 0 collisions and a path at most
1.3 x the shortest; goto's figures are reported as they are (the seed: "it can easily get trapped").

Usage: ``make bench-motion`` (all maps, 20 pairs) or ``python bench/nav_motion.py --pairs 5
--generated 2 --shipped office``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import pathlib
import random
import sys
import time
from collections.abc import Callable

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import nav_run  # noqa: E402

RADIUS = 0.35
ARRIVED_M = 0.4
GOAL_CLEARANCE_M = 0.6
GOAL_SPACING_M = 2.0
MAX_TV = 0.6


@dataclasses.dataclass
class PairResult:
    mode: str
    success: bool
    collision: bool
    seconds: float
    driven_m: float
    shortest_m: float


def pick_goals(map_file: pathlib.Path, count: int, seed: int) -> list[tuple[float, float]]:
    """``count`` goals from the map's start, each reachable from the one before."""
    from wurde_idl.mapfile import load_map_data

    from pluto_motion.grid_planner import Planner
    from pluto_motion.planning_grid import grid_from_map_file
    planner = Planner(grid_from_map_file(map_file))
    grid = planner.grid
    place = load_map_data(map_file).places['start']
    here = (place.x, place.y)
    free = [tuple(c) for c in zip(*grid.centre(*(grid.clearance >= GOAL_CLEARANCE_M).nonzero()))]
    rng = random.Random(seed)
    goals: list[tuple[float, float]] = []
    for _ in range(200 * count):
        if len(goals) == count:
            break
        goal = rng.choice(free)
        if math.dist(goal, here) >= GOAL_SPACING_M and planner.plan(here, goal).reachable:
            goals.append((float(goal[0]), float(goal[1])))
            here = goals[-1]
    return goals


class Shortest:
    """The shortest path of the robot's disc on the map (no comfort cost, no margin)."""

    def __init__(self, map_file: pathlib.Path) -> None:
        from pluto_motion.grid_planner import Planner, PlannerSettings
        from pluto_motion.planning_grid import GridSettings, grid_from_map_file
        self.planner = Planner(grid_from_map_file(map_file, GridSettings(margin=0.0)),
                               PlannerSettings(weight=0.0, keep=0.0))

    def length(self, start: tuple[float, float], goal: tuple[float, float]) -> float:
        plan = self.planner.plan(start, goal)
        return plan.length if plan.reachable else math.nan


def run_map(name: str, map_file: pathlib.Path, goals: list[tuple[float, float]], directory: pathlib.Path,
            mode: str, seed: int, *, prepare: Callable[[pathlib.Path], None] | None = None,
            on_truth: Callable[[float, float, float], None] | None = None) -> list[PairResult]:
    """Start config/pluto's robot on ``map_file`` and visit ``goals`` by ``mode`` (moveto, rays or goto)."""
    from wurde_core import CommsManager
    from wurde_core.interfaces import Bumper, Egomotion
    from wurde_drivers.sim.mapfile import load_map
    from wurde_testing import ChildProcess, find_executable

    from pluto_motion.motion_proxy import MotionProxy
    from pluto_motion.task import TaskResult

    nav_run.write_config(directory, map_file, estimator='poseModule', seed=seed, time_scale=1.0,
                         start_error=None, chain=True)
    if mode == 'rays':
        use_rays(directory / 'mcp-config.xml')
    if prepare is not None:
        prepare(directory)                      # e.g. people in the sim-config (bench/nav_people.py)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory),
               WURDE_DATA_DIR=str(directory))
    world, shortest = load_map(map_file), Shortest(map_file)
    manager = CommsManager(f'MotionBench{os.getpid()}')
    manager.set_no_sleep()
    motion = MotionProxy(manager)
    truth, bumpers = Egomotion('PlutoBaseTruth'), Bumper('PlutoBaseBumpers')
    for obj in (truth, bumpers):
        obj.set_queue_mode(True)
        manager.register_consumer(obj)
    path: list[tuple[float, float]] = []
    bumped = [False]

    def take() -> None:
        manager.step()
        motion.update()
        while truth.get_next_data():
            path.append((truth.data.location.x(), truth.data.location.y()))
            if on_truth is not None:
                on_truth(truth.data.timestamp.get_seconds(), *path[-1])
        while bumpers.get_next_data():
            bumped[0] = bumped[0] or bool(bumpers.data.bumped)

    def until(predicate, limit: float, every=None) -> bool:
        deadline, sent = time.monotonic() + limit, -math.inf
        while not predicate():
            if time.monotonic() > deadline:
                return False
            if every is not None and time.monotonic() - sent > 1.0:
                every()
                sent = time.monotonic()
            take()
            manager.wait(0.05)
        return True

    results = []
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(directory / 'mcp-config.xml'),
                           '-m', str(directory / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=120)
            if not until(lambda: path and motion.motion_status is not None and motion.goto_status not in (None, -10),
                         120, every=motion.start_activity):
                raise SystemExit(f'{name}: the chain did not come up (see {directory})')
            for goal in goals:
                start = path[-1]
                first, bumped[0] = len(path) - 1, False
                best = shortest.length(start, goal)
                limit = 30.0 + 3.0 * (best if math.isfinite(best) else math.dist(start, goal)) / 0.3
                began = time.monotonic()
                if mode in ('moveto', 'rays'):
                    task = motion.go_to(*goal, timeout=limit)
                    until(task.is_task_complete, limit + 5)
                    said, why = task.result() is TaskResult.SUCCEEDED, task.reason
                else:
                    command = lambda: motion.send(32, [MAX_TV, 1.0], list(goal), [1.0])  # noqa: E731
                    said = until(lambda: motion.goto_status == -1, 10.0, every=command) and \
                        until(lambda: motion.goto_status in (1, 2), limit) and motion.goto_status == 1
                    reasons: dict[int | None, str] = {2: 'stuck', 1: ''}
                    why = reasons.get(motion.goto_status, 'timeout')
                seconds = time.monotonic() - began
                motion.stop()
                until(lambda: False, 1.0)                    # the truth of the stop comes in
                leg = path[first:]
                near = min(world.distance_to_nearest_wall(p) for p in leg[::2] + leg[-1:])
                results.append(PairResult(mode, said and math.dist(leg[-1], goal) <= ARRIVED_M,
                                          bumped[0] or near < RADIUS, seconds,
                                          sum(math.dist(a, b) for a, b in zip(leg, leg[1:])), best))
                r = results[-1]
                print(f'  {name} {mode} {tuple(round(v, 1) for v in start)} -> {goal[0]:.1f},{goal[1]:.1f}: '
                      f'{"ok" if r.success else "FAILED"}{" COLLISION" if r.collision else ""} {r.seconds:.0f} s, '
                      f'{r.driven_m:.1f} m / shortest {r.shortest_m:.1f} m, nearest wall {near:.2f} m, ended at '
                      f'{leg[-1][0]:.2f},{leg[-1][1]:.2f}{" (" + why + ")" if why else ""}', flush=True)
    finally:
        manager.clean_up()
    return results


def use_rays(mcp_config: pathlib.Path) -> None:
    """The motionModule of ``mcp_config`` moves by ray following (``-R``) though it has the map."""
    from lxml import etree
    tree = etree.parse(str(mcp_config))
    for node in tree.getroot().iter('module'):
        if node.get('name') == 'motionModule':
            node.find('options').text += ' -R'
    tree.write(str(mcp_config))


LABELS = {'moveto': 'moveto (42)', 'rays': 'moveto, ray following (42, -R)', 'goto': 'goto (32)'}


def row(name: str, mode: str, results: list[PairResult]) -> str:
    ok = [r for r in results if r.success]
    ratios = [r.driven_m / r.shortest_m for r in ok if r.shortest_m > 0]
    collisions = sum(r.collision for r in results)
    mean_ratio = f'{sum(ratios) / len(ratios):.2f}' if ratios else '-'
    worst = f'{max(ratios):.2f}' if ratios else '-'
    seconds = f'{sum(r.seconds for r in ok) / len(ok):.0f}' if ok else '-'
    return (f'| {name} | {LABELS[mode]} | {len(results)} | '
            f'{100.0 * len(ok) / max(1, len(results)):.0f} % | {collisions} | {seconds} | {mean_ratio} | {worst} |')


HEADER = ('| map | command | pairs | success | collisions | mean time s (successes) | path / shortest, mean '
          '| path / shortest, worst |\n|' + '---|' * 8)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--pairs', type=int, default=20, help='start/goal pairs per map')
    parser.add_argument('--generated', type=int, default=3, help='generated maps (one per kind, cycling)')
    parser.add_argument('--seed', type=int, default=21, help='first seed of generated maps and goals')
    parser.add_argument('--kinds', default='', help='kinds of generated maps, comma-separated (default all)')
    parser.add_argument('--shipped', default='office,corridor-loop,outdoor', help='shipped maps to run')
    parser.add_argument('--modes', default='moveto,goto', help='moveto, rays (ray following), goto')
    args = parser.parse_args()
    work, maps = nav_run.bench_setup('make bench-motion', args.shipped, args.generated, args.seed, args.kinds)
    table = []
    for i, (name, path) in enumerate(maps):
        goals = pick_goals(path, args.pairs, args.seed + i)
        for mode in args.modes.split(','):
            results = run_map(name, path, goals, work / f'{mode}{i}', mode, args.seed + i)
            table.append(row(name, mode, results))
            print(HEADER + '\n' + '\n'.join(table), flush=True)
    print(f'(runs in {work})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
