"""``mission``: send the robot through named places of its map by moveto, and show how it goes.

    mission [-m MAP] [-P place,place,...] [-O DIR] [-t SECONDS] [-T TRUTH] [-L LASER]

The client of ``make demo`` (the main job): for each place of ``-P`` (names from the map's place
list; an unknown name is skipped with a warning, as CARMEN's navigator ignores an unknown place),
CARMEN's ``set_goal_place(name)`` and ``go`` to the navigator (:mod:`pluto_motion.navigator`,
which drives by the motionModule's moveto), waiting until it stops autonomous motion and says why.
An entry ``explore:NAME`` explores the room of place NAME (:mod:`pluto_motion.room`: its bounds
on the planner's grid): the navigator takes the robot to the explore's home, the middle of
one side, it turns to face into the room, and the motionModule's explore (Pluto 6.3, cmdFlags 44)
covers the room in lanes and comes back home; then the explore's rectangle is removed, so that
the next goals outside it are not refused.  The terminal shows live progress (rich): the goal, the distance left, the
Localization/Pose and its error against the simulator's truth (``-T``, default ``PlutoBaseTruth``;
``-T ''`` none), and the modules' run states from the MCP's table.  At the end a summary table
(goals reached, time, distance, pose RMSE, wall contacts) and ``DIR/mission.png``
(:mod:`pluto_motion.mission_plot`).  Exit status 0 when every goal was reached without a contact.
"""

from __future__ import annotations

import math
import pathlib
import sys
import time
from collections.abc import Callable

from rich.console import Console, Group
from rich.live import Live
from rich.table import Table
from wurde_core import CommsManager, RunState
from wurde_core.heartbeat import mcp_name
from wurde_core.interfaces import Egomotion, Navigator, RangeFinder, SimpleControl
from wurde_core.mcp_client import control_stream
from wurde_core.module_loop import config_file
from wurde_core.wrappers import GOAL_REACHED, STOP_FAILED, STOP_NONE, USER_STOPPED
from wurde_idl.errors import ConfigError
from wurde_idl.maps import load_map

from pluto_nav.loc_proxy import LocProxy
from pluto_nav.pose_history import TRUTH_GAP_S, PoseHistory
from pluto_nav.streams import POSE

from .mission_log import Goal, MissionLog, Sample
from .mission_plot import plot_mission
from .motion_behaviours import TURN
from .motion_proxy import MotionProxy
from .planning_grid import PlanningGrid, build_grid
from .ray_follow import ScanGeometry, geometry_from_info, scan_points
from .room import ExploreArea, explore_area
from .task import TaskResult

__all__ = ['DEFAULT_PLACES', 'EXPLORE', 'STOP_REASONS', 'main']

#: The office tour of ``make demo``: office2 and its room explored, the lab, the kitchen and back.
DEFAULT_PLACES = ('office2', 'explore:office2', 'lab', 'kitchen', 'start')
#: An entry of -P that explores the room of a place.
EXPLORE = 'explore:'
#: Explore's rectangle keeps this far inside the room's bounds (m): the robot (radius 0.35 m) stops
#: short of a goal nearer a wall than its laser protection allows.
EXPLORE_MARGIN = 1.0
#: A heading this near the explore's is faced into the room (rad).
FACING = math.radians(5.0)
#: The robot's radius (m): a truth nearer a wall is a contact.
RADIUS = 0.35
SAMPLE_S = 0.1
#: Seconds of truth kept to pair with the pose of its stamp (a pose older is not compared).
TRUTH_KEEP_S = 5.0
#: How the navigator's stop reasons read in the mission's report.
STOP_REASONS = {GOAL_REACHED: 'reached', USER_STOPPED: 'stopped by the user',
                STOP_FAILED: 'not reached (the navigator\'s log says why)'}
START_TIMEOUT_S = 120.0
#: Seconds between sends of a goal the navigator's status does not show it driving to.
RESEND_S = 2.0
#: Seconds without a Pose that make the mission say what it hears (a view that stopped is stale).
STALL_S = 10.0
HELP = ('  -m MAP       the map file (default map.xml of the config directory)\n'
        f'  -P PLACES    comma-separated place names, explore:NAME explores the room of place NAME\n'
        f'               (default {",".join(DEFAULT_PLACES)})\n'
        '  -O DIR       where mission.png goes (default the data directory)\n'
        '  -t SECONDS   longest time per goal (default 240)\n'
        '  -T STREAM    the simulator\'s truth (default PlutoBaseTruth; empty: none)\n'
        '  -L LASER     the laser whose last scan the plot shows (default PlutoLaser; empty: none)')


class Mission:
    """The streams the mission reads and the log it keeps."""

    def __init__(self, manager: CommsManager, walls: list, truth: str, laser: str = 'PlutoLaser') -> None:
        self.manager = manager
        self.motion = MotionProxy(manager)
        self.loc = LocProxy(manager, 1 << POSE)
        self.truth = Egomotion(truth) if truth else None
        if self.truth is not None:
            self.truth.set_queue_mode(True)
        self.table = SimpleControl(control_stream(mcp_name()))  # its own MCP's table
        self.nav = Navigator('Navigator')
        self.nav.set_queue_mode(True)
        self.laser = RangeFinder(laser) if laser else None
        self.geometry: ScanGeometry | None = None
        #: Every navigator status: (autonomous, stop_reason, goal x, goal y).
        self.statuses: list[tuple[bool, int, float, float]] = []
        for obj in (self.truth, self.table, self.nav, self.laser):
            if obj is not None:
                manager.register_consumer(obj)
        self.log = MissionLog(walls, RADIUS)
        self.latest_truth: tuple[float, float, float] | None = None
        #: The truth by its stamps (the robot's clock, as the pose's): the pose is compared with
        #: the truth of its own moment.
        self.truths = PoseHistory(keep_s=TRUTH_KEEP_S, max_gap_s=TRUTH_GAP_S)
        self.modules: dict[str, str] = {}
        self._sampled = -math.inf
        self.start = time.monotonic()
        self._heard = (-1, self.start)          # Poses received, and since when that many
        self._stall_said = False

    def take(self) -> None:
        """Take in the truth and the MCP's table; a sample every :data:`SAMPLE_S`."""
        self.motion.update()
        if self.truth is not None:
            while self.truth.get_next_data():
                loc = self.truth.data.location
                self.latest_truth = (loc.x(), loc.y(), loc.theta())
                self.truths.add(self.truth.data.timestamp.get_seconds(), self.latest_truth)
        while self.nav.get_next_data():
            d = self.nav.data
            self.statuses.append((bool(d.autonomous), int(d.stop_reason), d.goal.x(), d.goal.y()))
        while self.table.get_next_data():
            d = self.table.data
            self.modules = {n: RunState(s).name for n, s in zip(d.module_names, d.module_state)}
        pose = self.loc.get_pose(POSE)
        if self.laser is not None:
            if self.laser.get_next_info():
                self.geometry = geometry_from_info(self.laser.info)
            if self.laser.get_next_data() and self.geometry is not None and pose is not None:
                self.log.last_scan = scan_points(list(self.laser.data.ranges),
                                                 (pose.pose[0], pose.pose[1], pose.pose[3]), self.geometry)
        now = time.monotonic()
        self._watch_stall(now)
        if pose is not None and now - self._sampled >= SAMPLE_S:
            self._sampled = now
            self.log.add(Sample(now - self.start, (pose.pose[0], pose.pose[1], pose.pose[3]),
                                pose.covariance, self.latest_truth, self.truths.at(pose.stamp)))

    def _watch_stall(self, now: float) -> None:
        """Say once per stall when no Pose came for :data:`STALL_S`: what each stream has
        received and how many writers it has matched, so a view gone stale is not taken for the
        robot's (a soak's mission once heard nothing for minutes while the navigator drove)."""
        heard = self.loc.streams[POSE].received()
        if heard != self._heard[0]:
            self._heard, self._stall_said = (heard, now), False
            return
        if self._stall_said or now - self._heard[1] < STALL_S:
            return
        self._stall_said = True
        objects = [self.loc.streams[POSE], self.nav, self.truth, self.table]
        heard_of = '; '.join(f'{obj.object_name}: {obj.received()} received, {obj.peers("data")} writers'
                             for obj in objects if obj is not None)
        self.manager.log_warning(f'no Pose for {now - self._heard[1]:.0f} s ({heard_of}; '
                                 f'run state {RunState(self.manager.state).name})')

    def view(self, goal: Goal | None) -> Group:
        """The live view: the goal's line and the modules' states."""
        table = Table(title='Pluto mission', expand=False)
        for column in ('goal', 'distance left', 'pose (x, y, theta)', 'error vs truth', 'time'):
            table.add_column(column)
        sample = self.log.samples[-1] if self.log.samples else None
        if goal is not None and sample is not None:
            x, y, theta = sample.pose
            error = f'{math.dist(sample.pose[:2], sample.pose_truth[:2]):.2f} m' if sample.pose_truth else '-'
            table.add_row(goal.name, f'{math.dist((x, y), (goal.x, goal.y)):.2f} m',
                          f'{x:.2f}, {y:.2f}, {theta:.2f}', error, f'{sample.t:.0f} s')
        running = sum(state == 'RUN' for state in self.modules.values())
        others = ', '.join(f'{n} {s}' for n, s in sorted(self.modules.items()) if s != 'RUN')
        modules = f'modules: {running} of {len(self.modules)} in RUN' + (f' ({others})' if others else '')
        return Group(table, modules)

    def until_running(self) -> bool:
        """Wait for the chain (motion and avoid statuses), the navigator and a pose; start the
        chain's threads."""
        deadline = time.monotonic() + START_TIMEOUT_S
        sent = -math.inf
        while not (self.motion.motion_status is not None and self.motion.goto_status not in (None, -10)
                   and self.log.samples and self.statuses and self.nav.peers('request') > 0):
            if time.monotonic() > deadline or self.manager.run_update(0.05) != RunState.RUN:
                return False
            if time.monotonic() - sent > 1.0:
                self.motion.start_activity()
                sent = time.monotonic()
            self.take()
        return True


    def _turn(self, on_turn: Callable[[], object]) -> bool:
        """One turn of the client's loop; False when the mission is told to quit."""
        if self.manager.run_update() != RunState.RUN:
            return False
        self.manager.wait(0.05)
        self.take()
        on_turn()
        return True

    def visit(self, goal: Goal, timeout: float, on_turn: Callable[[], object], *, by_place: bool = True) -> str:
        """Send the navigator to ``goal`` — by its place name, or (``by_place`` False) by its
        coordinates — and go; how it ended: ``reached``, or why not.

        The goal and go are sent again every :data:`RESEND_S` while the navigator's status does
        not show it driving to ``goal`` (issue 38: a request sent while the navigator restarts is
        lost, and a navigator restarted before it kept the goal comes back idle); a refusal of
        ``goal`` (stop reason 3) ends the visit at once.
        """
        mark = len(self.statuses)
        deadline = time.monotonic() + timeout
        started = held = False
        sent = -math.inf
        while True:
            if not held and time.monotonic() - sent >= RESEND_S:
                if by_place:
                    self.nav.set_goal_place(goal.name)
                else:
                    self.nav.set_goal(goal.x, goal.y)
                self.nav.go()
                sent = time.monotonic()
            if not self._turn(on_turn):
                return 'the mission was told to quit'
            for autonomous, reason, x, y in self.statuses[mark:]:
                mark += 1
                ours = math.isclose(x, goal.x, abs_tol=1e-3) and math.isclose(y, goal.y, abs_tol=1e-3)
                held = autonomous and ours
                started = started or held
                if not autonomous and ((started and reason != STOP_NONE) or (ours and reason == STOP_FAILED)):
                    return STOP_REASONS.get(reason, f'stopped ({reason})')
            if time.monotonic() > deadline:
                self.nav.stop()
                return f'not reached within {timeout:g} s'

    def explore(self, goal: Goal, area: ExploreArea, timeout: float, on_turn: Callable[[], object]) -> str:
        """Explore ``area`` (the room ``goal`` names; ``goal`` is its home): to the home by the
        navigator, face into the room, the motionModule's explore, the rectangle removed after;
        ``reached`` once home again, or why not."""
        result = self.visit(goal, timeout, on_turn, by_place=False)
        if result != 'reached':
            return f'home not reached: {result}'
        deadline = time.monotonic() + timeout
        sent = -math.inf
        while True:                                 # turn in place (the avoid regulator, speed 0)
            pose = self.loc.get_pose(POSE)
            if pose is not None and abs(math.remainder(pose.pose[3] - area.theta, math.tau)) < FACING:
                break
            if time.monotonic() > deadline:
                return 'did not turn into the room'
            if time.monotonic() - sent > 1.0:
                self.motion.send(TURN, velocity=[0.0], position=[0.0, area.theta])
                sent = time.monotonic()
            if not self._turn(on_turn):
                return 'the mission was told to quit'
        task = self.motion.explore_task(area.b, area.h, timeout=timeout, spin=False)
        try:
            while not task.is_task_complete():
                if not self._turn(on_turn):
                    task.cancel()
                    return 'the mission was told to quit'
        finally:
            self.motion.set_rectangle(0.0, 0.0)     # the explore's rectangle would limit every goal
        return 'reached' if task.result() is TaskResult.SUCCEEDED else f'explore: {task.reason}'


def _summary_table(mission: Mission) -> Table:
    s = mission.log.summary()
    table = Table(title='Mission summary')
    table.add_column('figure')
    table.add_column('value', justify='right')
    rows = [('goals reached', f'{s.reached} of {s.goals}'), ('time', f'{s.seconds:.1f} s'),
            ('distance (truth)', f'{s.distance:.1f} m'), ('pose RMSE vs truth', f'{s.pose_rmse:.3f} m'),
            ('largest pose error', f'{s.pose_max:.3f} m'),
            ('wall contacts', str(s.contacts) if s.contacts >= 0 else 'no truth'),
            ('least clearance', f'{s.clearance - RADIUS:.2f} m beyond the radius')]
    for name, value in rows:
        table.add_row(name, value)
    for goal in mission.log.goals:
        took = f'{goal.ended - goal.started:.1f} s' if goal.ended is not None else '-'
        table.add_row(f'  {goal.name}', f'{goal.result} ({took})')
    return table


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('mission')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'm:P:O:t:T:L:').user
    console = Console()
    try:
        world = load_map(config_file(manager, opts.get('m'), 'map.xml'))
    except ConfigError as exc:
        print(f'mission: {exc}', file=sys.stderr, flush=True)
        return 2
    names = [n.strip() for n in opts.get('P', ','.join(DEFAULT_PLACES)).split(',') if n.strip()]
    steps: list[tuple[str, ExploreArea | None]] = []
    grid: PlanningGrid | None = None
    for name in names:
        place = name.removeprefix(EXPLORE)
        if place not in world.places:
            console.print(f'mission: warning: no place "{place}" on map {world.name}; skipped '
                          f'(places: {", ".join(world.places)})')
            continue
        if place == name:
            steps.append((name, None))
            continue
        try:
            grid = grid or build_grid(world.walls, world.offlimits, world.bounds)
            steps.append((name, explore_area(grid, world.places[place].x, world.places[place].y,
                                             EXPLORE_MARGIN)))
        except ValueError as error:
            console.print(f'mission: warning: {name}: {error}; skipped')
    output = pathlib.Path(opts.get('O') or manager.config.get_data_directory() or '.')
    timeout = float(opts.get('t', 240.0))
    mission = Mission(manager, list(world.walls), opts.get('T', 'PlutoBaseTruth'), opts.get('L', 'PlutoLaser'))
    try:
        if not mission.until_running():
            console.print('mission: the movement chain did not come up')
            return 1
        console.print(f'mission: the chain runs; visiting {", ".join(name for name, _ in steps)}')
        with Live(mission.view(None), console=console, refresh_per_second=4) as live:
            for name, area in steps:
                where = world.places[name] if area is None else area
                goal = Goal(name, where.x, where.y, time.monotonic() - mission.start)
                mission.log.goals.append(goal)
                def show(goal: Goal = goal) -> None:
                    live.update(mission.view(goal))
                if area is None:
                    goal.result = mission.visit(goal, timeout, show)
                else:
                    goal.result = mission.explore(goal, area, timeout, show)
                goal.ended = time.monotonic() - mission.start
                live.console.print(f'mission: {name} ({where.x:g}, {where.y:g}): {goal.result} '
                                   f'after {goal.ended - goal.started:.1f} s')
        console.print()
        console.print(_summary_table(mission))
        output.mkdir(parents=True, exist_ok=True)
        plot_mission(mission.log, output / 'mission.png', f'Pluto mission on {world.name}')
        console.print(f'mission: plot in {output / "mission.png"}')
        summary = mission.log.summary()
        return 0 if summary.reached == summary.goals == len(names) and summary.contacts <= 0 else 1
    finally:
        manager.clean_up()


if __name__ == '__main__':
    sys.exit(main())
