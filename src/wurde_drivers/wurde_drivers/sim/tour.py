"""tour: a client that drives the (simulated) robot through waypoints and plots the run.

A user program like the guide's: it declares the robot's objects by stream name and uses them —
RobotDrive to command, Egomotion odometry to know where it is, the laser to slow down and stop
before obstacles, the bumpers to give up — with no idea whether the robot is a dummy. Its pose is
the odometry started at the map's ``start`` place, as Pluto's localModule reads its starting pose
from a file (3). When done (or on Quit) it prints what it saw and saves a plot (map, true path,
odometry, last laser scan) as PNG.

Options: ``-c sim-config.xml`` (the base, laser and map names), ``-w "x,y x,y ..."`` (waypoints in
the map frame; default: a tour of the office map), ``-p FILE`` (the PNG, default
``<data dir>/tour.png``), ``-t SECONDS`` (give up after this long, default 300), ``-L STREAM``
(steer by a localization's poses, a LocalizationPose stream such as Pluto's ``Localization/Pose``,
instead of the odometry; the plot then shows its path too).
"""

from __future__ import annotations

import math
import pathlib
import sys
import time

from wurde_core import CommsManager, Logger, RunState
from wurde_core.interfaces import (
    Bumper,
    Egomotion,
    LocalizationPose,
    RangeFinder,
    RobotDrive,
    SynchroDrive,
)
from wurde_idl.errors import ConfigError

from ..module_setup import config_file, exit_on_config_error
from .loading import load_sim
from .plot import plot_run

#: The default route through the office map: along the corridor, into the lab and the
#: conference room, and back to the start.
OFFICE_ROUTE = '8,7.5 12.5,7.5 12.5,4.2 12.5,7.5 10,7.5 10,9.6 10,7.5 3.5,7.5'
REACHED_M = 0.1
LOOP_S = 0.05   # control period (wall clock)
WAIT_FOR_BASE_S = 60.0
TURN_FIRST_RAD = 0.35   # turn on the spot before driving when the heading is this far off
MAX_TV = 0.6
MAX_RV = 1.0
#: m: the robot steers for a point this far ahead along the leg it is on, not for the waypoint:
#: the route's legs are what keeps clear of the walls (with a few centimetres to spare in a door),
#: and a robot that reached a waypoint some centimetres off would otherwise drive a parallel line.
LOOKAHEAD_M = 0.4
#: m: a waypoint the robot has passed along its leg counts as reached within this distance.
PASSED_M = 0.3
#: s (simulated): the heading error is taken out over this long (a gain of 1.5 rad/s per rad), or
#: over two control periods when they are longer; the distance to a waypoint likewise (_horizon).
SETTLE_S = 1.0 / 1.5
SLOW_M = 1.2     # laser: slow down when something is this close ahead
STOP_M = 0.45    # laser: stop
#: m from the footprint's edge: anything in the laser's half plane nearer than this (a door's
#: jambs) slows the robot down to :data:`NARROW_SHARE` of its speed at :data:`NARROW_MIN_M`, so
#: that a late command (a loaded machine) moves it sideways by less than the clearance it has.
NARROW_M = 0.5
NARROW_MIN_M = 0.1
NARROW_SHARE = 0.25


def waypoint_reached(distance: float, covered: float, ahead: float) -> str | None:
    """Whether the waypoint ``distance`` m away counts as reached ('' or why), after ``covered``
    (share of its leg driven) with the laser's nearest reading ``ahead`` (m) straight ahead.

    Within :data:`REACHED_M`; or passed along its leg within :data:`PASSED_M`; or within
    :data:`PASSED_M` while the laser stops the robot (something within :data:`STOP_M` ahead): a
    generated route may put a waypoint 0.4 m from a wall (its clearance), nearer than the laser
    lets the robot go, and the tour stood there until its time ran out (`make bench-nav`)."""
    if distance < REACHED_M or (covered >= 1.0 and distance < PASSED_M):
        return ''
    if distance < PASSED_M and ahead <= STOP_M:
        return f' (as near as the laser allows: {ahead:.2f} m ahead)'
    return None


def _route(text: str) -> list[tuple[float, float]]:
    points = []
    for item in text.split():
        x, y = item.split(',')
        points.append((float(x), float(y)))
    return points


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def _horizon(period_s: float) -> float:
    """Simulated seconds over which a command may take out the error it was computed from.

    A command acts until the next one, one control period later; the period is in wall seconds
    times the simulator's time scale, and on a loaded machine it stretches.  A fixed gain would
    turn (or drive) by more than the error in one long period and the loop would oscillate; with
    the error taken out over at least two periods each command does at most half of it, so the
    loop stays stable however long the period gets.
    """
    return max(SETTLE_S, 2.0 * period_s)


def _along(leg_start: tuple[float, float], goal: tuple[float, float],
           position: tuple[float, float]) -> tuple[float, tuple[float, float]]:
    """Where ``position`` is along the leg: the fraction of it covered (its projection, may be
    below 0 or above 1) and the point :data:`LOOKAHEAD_M` beyond the projection (within the leg)."""
    dx, dy = goal[0] - leg_start[0], goal[1] - leg_start[1]
    length = math.hypot(dx, dy)
    if length < 1e-9:
        return 1.0, goal
    covered = ((position[0] - leg_start[0]) * dx + (position[1] - leg_start[1]) * dy) / length ** 2
    t = min(1.0, max(0.0, covered) + LOOKAHEAD_M / length)
    return covered, (leg_start[0] + t * dx, leg_start[1] + t * dy)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('Tour')
    manager.set_help_string('  -c FILE  sim-config.xml\n  -w "x,y x,y"  waypoints\n'
                            '  -p FILE  plot (PNG)\n  -t SECONDS  give up after this long\n'
                            '  -L STREAM  steer by this LocalizationPose stream (e.g. Localization/Pose)')
    opts = manager.parse_options(argv, 'c:w:p:t:L:')
    path = config_file(manager, opts.user.get('c'), 'sim-config.xml')
    try:
        config, world, start = load_sim(path)
        route = _route(opts.user.get('w', OFFICE_ROUTE))
        limit_s = float(opts.user.get('t', '300'))
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        print(f'tour: bad -w or -t: {error}', file=sys.stderr)
        return 2
    plot_file = opts.user.get('p') or str(pathlib.Path(manager.config.get_data_directory()) / 'tour.png')
    base = config.base.name
    laser_name = next(iter(config.lasers), None)
    drive = (SynchroDrive if config.base.synchro else RobotDrive)(f'{base}Drive')
    odometry = Egomotion(f'{base}Motion')
    truth = Egomotion(config.base.truth_stream)      # for the plot only, never for steering
    bumpers = Bumper(f'{base}Bumpers')
    laser = RangeFinder(laser_name) if laser_name else None
    localization = LocalizationPose(opts.user['L']) if opts.user.get('L') else None
    logger = Logger(manager.name)
    for obj in (drive, odometry, truth, bumpers) + ((laser,) if laser else ()) + \
            ((localization,) if localization else ()):
        manager.register_consumer(obj)
    manager.register_supplier(logger)
    manager.set_sleep(LOOP_S)

    sx, sy, st = start
    radius = config.robot.bumpers.radius   # the footprint

    def pose() -> tuple[float, float, float]:
        if localization is not None:
            p = localization.data.pose
            return p.x(), p.y(), p.theta()
        loc = odometry.data.location
        ox, oy, ot = loc.x(), loc.y(), loc.theta()
        return (sx + ox * math.cos(st) - oy * math.sin(st), sy + ox * math.sin(st) + oy * math.cos(st), st + ot)

    def command(tv: float, rv: float) -> None:
        if config.base.synchro:
            drive.requests.trans.set_value(tv)
            drive.requests.angular.set_value(rv)
        else:
            drive.requests.trans_velocity.set_value(tv)
            drive.requests.rot_velocity.set_value(rv)
        drive.publish_request()

    print(f'tour: {len(route)} waypoints in {world.name}, from {start}', flush=True)
    truth_path: list[tuple[float, float]] = []
    odo_path: list[tuple[float, float]] = []
    estimate_path: list[tuple[float, float]] = []
    last_scan: list[float] = []
    scan_pose = None
    target = 0
    leg_start = (sx, sy)
    have_odometry = False
    bumped = False
    started = time.monotonic()
    last_report = 0.0
    last_command = time.monotonic()
    while manager.run_update() == RunState.RUN:
        while truth.get_next_data():
            loc = truth.data.location
            truth_path.append((loc.x(), loc.y()))
        while odometry.get_next_data():
            have_odometry = have_odometry or localization is None
            loc = odometry.data.location
            ox, oy = loc.x(), loc.y()
            odo_path.append((sx + ox * math.cos(st) - oy * math.sin(st), sy + ox * math.sin(st) + oy * math.cos(st)))
        while localization is not None and localization.get_next_data():
            have_odometry = True
            x, y, _ = pose()
            estimate_path.append((x, y))
        if laser is not None:
            while laser.get_next_data():
                last_scan = list(laser.data.ranges)
                scan_pose = pose() if have_odometry else None
        while bumpers.get_next_data():
            if bumpers.data.bumped and not bumped:
                bumped = True
                print('tour: bumper pressed: stopping', flush=True)
        if not have_odometry:
            if time.monotonic() - started > WAIT_FOR_BASE_S:
                source = opts.user.get('L') or f'{base}Motion'
                print(f'tour: no pose from {source} after {WAIT_FOR_BASE_S:.0f} s; is it running?',
                      file=sys.stderr, flush=True)
                break
            continue
        if bumped or target >= len(route) or time.monotonic() - started > limit_s:
            command(0.0, 0.0)
            break
        x, y, theta = pose()
        gx, gy = route[target]
        distance = math.hypot(gx - x, gy - y)
        covered, (cx, cy) = _along(leg_start, (gx, gy), (x, y))
        heading_error = _wrap(math.atan2(cy - y, cx - x) - theta)
        ahead = min((r for i, r in enumerate(last_scan) if abs(i - len(last_scan) // 2) <= len(last_scan) // 12),
                    default=math.inf)
        why = waypoint_reached(distance, covered, ahead)
        if why is not None:
            print(f'tour: reached waypoint {target + 1}/{len(route)} ({gx:.1f}, {gy:.1f}) at '
                  f'({x:.2f}, {y:.2f}){why}', flush=True)
            target += 1
            leg_start = (gx, gy)
            continue
        now = time.monotonic()
        horizon = _horizon(max(LOOP_S, now - last_command) * config.time_scale)
        # Full speed only when facing the waypoint, none from TURN_FIRST_RAD off: what the robot
        # drives while its heading error is taken out moves it sideways, and doors are narrow.
        aligned = math.cos(min(abs(heading_error) / TURN_FIRST_RAD, 1.0) * math.pi / 2)
        # And no faster than covers half the look-ahead in a control period: when the period
        # stretches, the leg is still tracked rather than overshot sideways.
        tv = min(MAX_TV * aligned * min(1.0, distance), distance / horizon, LOOKAHEAD_M / horizon)
        if ahead < SLOW_M:
            tv *= max(0.0, (ahead - STOP_M) / (SLOW_M - STOP_M))
        clearance = min(last_scan, default=math.inf) - radius
        if clearance < NARROW_M:
            tv *= max(NARROW_SHARE, min(1.0, (clearance - NARROW_MIN_M) / (NARROW_M - NARROW_MIN_M)))
        rv = max(-MAX_RV, min(MAX_RV, heading_error / horizon))
        command(tv, rv)
        last_command = now
        if now - last_report >= 2.0:
            last_report = now
            print(f'tour: at ({x:.2f}, {y:.2f}, {math.degrees(theta):.0f} deg), going to waypoint '
                  f'{target + 1} ({gx:.1f}, {gy:.1f}), {distance:.2f} m away; nearest thing ahead '
                  f'{ahead:.2f} m', flush=True)
    command(0.0, 0.0)
    reached = target >= len(route)
    distance_driven = sum(math.dist(a, b) for a, b in zip(truth_path, truth_path[1:]))
    print(f'tour: {"all" if reached else target} of {len(route)} waypoints reached, '
          f'{distance_driven:.1f} m driven in {time.monotonic() - started:.1f} s', flush=True)
    if truth_path:
        final = truth_path[-1]
        x, y, _ = pose()
        print(f'tour: {"localization" if localization else "odometry"} ends at ({x:.2f}, {y:.2f}), '
              f'truth at ({final[0]:.2f}, {final[1]:.2f})', flush=True)
    plot_run(world, plot_file, truth=truth_path, odometry=odo_path, estimate=estimate_path, scan_pose=scan_pose,
             scan=last_scan, waypoints=route, title=f'{world.name}: tour of {len(route)} waypoints')
    print(f'tour: plot saved to {plot_file}', flush=True)
    manager.clean_up()
    return 0 if reached else 1


if __name__ == '__main__':
    sys.exit(main())
