"""Benchmark: the movement chain among people (issue 38's `make bench-people`).

On the shipped maps and generated ones, config/pluto's whole robot (dummies with noise, localModule,
poseModule, drive, avoid, motion planning on the map) visits ``--pairs`` goals by moveto (cmdFlags
42), first on the empty map and then, in the same process, with 1-5 people crossing its way
(:mod:`people_course`: back and forth across the planned way between goals, 0.5 m/s up to
``--speed``, discs and trolleys). Per map and number of people: goals reached, contacts with people
(each new touch of the robot's disc and a person's body, at the truth's stamps; each one's kind
below the table: who moved, and whether the person had set off within 1 s), the least
clearance to a person, collisions (a bumper pressed, or the truth nearer a wall than the
radius), and the time lost against the empty map over the legs that both runs drove from the same
goal to the same goal (both reached the leg's start and end).

The simulated people neither yield nor stop for the robot (scripted walks): a contact where a
person walked into a robot that had stopped is counted as much as one the robot drove into.

Usage: ``make bench-people`` or ``python bench/nav_people.py --pairs 4 --people 1,3,5
--generated 1 --shipped office``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import nav_motion  # noqa: E402
import nav_run  # noqa: E402
import people_course  # noqa: E402


@dataclasses.dataclass
class Outcome:
    """One run's figures: the pairs' results and the clearance to people."""

    results: list
    people: int
    contacts: int
    least_m: float
    kinds: dict


def run(name: str, map_file: pathlib.Path, goals, work: pathlib.Path, people: int, seed: int,
        speed: float) -> Outcome:
    """Visit ``goals`` by moveto with ``people`` people crossing the way (0: the empty map)."""
    from wurde_drivers.sim.loading import load_sim
    placed: list = []
    clearance: list = []

    def prepare(directory: pathlib.Path) -> None:
        sim_config = directory / 'sim-config.xml'
        if people:
            placed.extend(people_course.crossing_people(sim_config, map_file, goals, people, seed, speed))
            people_course.write_people(sim_config, placed)
        _, world, _ = load_sim(str(sim_config))
        clearance.append(people_course.Clearance(world.people, nav_motion.RADIUS))

    def on_truth(stamp: float, x: float, y: float) -> None:
        clearance[0].add(stamp, x, y)

    results = nav_motion.run_map(name, map_file, goals, work, 'moveto', seed, prepare=prepare, on_truth=on_truth)
    return Outcome(results, len(placed), clearance[0].contacts, clearance[0].least, dict(clearance[0].kinds))


def row(name: str, outcome: Outcome, empty: Outcome) -> str:
    results = outcome.results
    ok = sum(r.success for r in results)
    walls = sum(r.collision for r in results)
    # A goal's time compares only when both runs started it from the previous goal (both reached).
    reached = [r.success and e.success for r, e in zip(results, empty.results)]
    both = [(r.seconds, e.seconds) for i, (r, e) in enumerate(zip(results, empty.results))
            if reached[i] and (i == 0 or reached[i - 1])]
    lost = f'{sum(a - b for a, b in both):+.0f}' if both and outcome.people else '-'
    least = f'{outcome.least_m:.2f}' if math.isfinite(outcome.least_m) else '-'
    return (f'| {name} | {outcome.people} | {ok} of {len(results)} | {outcome.contacts} | {least} | {walls} | '
            f'{sum(r.seconds for r in results):.0f} | {lost} |')


HEADER = ('| map | people | goals reached | contacts with people | least clearance to a person m '
          '| collisions (bumper or wall) | time s | time lost s (legs from and to goals reached in both runs) |\n|'
          + '---|' * 8)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--pairs', type=int, default=6, help='goals per map')
    parser.add_argument('--people', default='1,3,5', help='numbers of people, comma-separated')
    parser.add_argument('--speed', type=float, default=1.0, help='fastest walking speed (m/s, at most 1.5)')
    parser.add_argument('--generated', type=int, default=2, help='generated maps (one per kind, cycling)')
    parser.add_argument('--seed', type=int, default=38, help='first seed of maps, goals and people')
    parser.add_argument('--kinds', default='rooms,maze', help='kinds of generated maps, comma-separated')
    parser.add_argument('--shipped', default='office', help='shipped maps to run')
    args = parser.parse_args()
    work, maps = nav_run.bench_setup('make bench-people', args.shipped, args.generated, args.seed, args.kinds)
    table: list[str] = []
    kinds: list[str] = []
    for i, (name, path) in enumerate(maps):
        goals = nav_motion.pick_goals(path, args.pairs, args.seed + i)
        empty = run(name, path, goals, work / f'empty{i}', 0, args.seed + i, args.speed)
        table.append(row(name, empty, empty))
        for count in (int(n) for n in args.people.split(',')):
            outcome = run(name, path, goals, work / f'people{i}-{count}', count, args.seed + i, args.speed)
            table.append(row(name, outcome, empty))
            kinds.append(f'{name}, {count} people: ' + ('; '.join(f'{n} {kind}' for kind, n in sorted(
                outcome.kinds.items())) or 'no contact'))
            print(HEADER + '\n' + '\n'.join(table) + '\n\nContacts by kind:\n' + '\n'.join(kinds), flush=True)
    print(f'(runs in {work})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
