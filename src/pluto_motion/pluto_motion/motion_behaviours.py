"""The motionModule's behaviours (Pluto 6.3), free of I/O: moveto (planned on a map, or ray
following without one), investigate and explore.  Each is stepped with what the module knows now
(:class:`Situation`) and answers with a :class:`Step`: the avoid request to have in force (the
module sends it when it changes) and the status codes element[2], element[3].

A planned moveto follows its path with the avoidModule's regulator and laser protection
(:mod:`pluto_motion.path_follow`) and ends with the simple avoid goto on the last
:attr:`MotionSettings.near` metres (element[2] = -2, Pluto 6.3: "nearing moveto point (now using
simple goto)"); when it stops getting nearer it replans round what the laser sees.  Elsewhere the
avoid goto (cmdFlags 32: laser and sonar avoidance, Pluto 6.2) reaches each point; a point counts
as reached when the avoidModule reports element[1] = 1 for it, or when the pose is within
:attr:`MotionSettings.reach` of it; stuck (element[1] = 2) makes moveto replan and investigate or
explore skip the point.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable, Sequence

import numpy as np
from scipy.spatial import cKDTree
from numpy.typing import NDArray

from .grid_planner import Planner
from .path_follow import FollowSettings, PathFollower, Progress
from .motion_command import (APPROACHING, AT_GOAL, BLOCKED, CIRCLING, FOLLOWING, INVESTIGATE_DONE, MOVETO_SET,
                             NEARING, SCANNING, UNREACHABLE, Rectangle)
from .ray_follow import Action, RaySettings, decide

__all__ = ['AvoidRequest', 'Explore', 'Investigate', 'MotionSettings', 'Moveto', 'STOP', 'Situation', 'Step']

log = logging.getLogger(__name__)

#: avoidance/command: goto with laser and sonar avoidance; regulator with laser protection (turning
#: on the spot, and following a planned path: :mod:`pluto_motion.path_follow`).
GOTO, TURN = 32, 21
FOLLOW = TURN
#: element[1] of avoidance/status (Pluto 6.2).
GOTO_REACHED, GOTO_STUCK, GOTO_NORMAL = 1, 2, -1
#: Seconds investigate looks for scan points (an object to go to) before it ends with none.
LOOK_S = 5.0


@dataclasses.dataclass(frozen=True)
class MotionSettings:
    """Distances m, speeds m/s and rad/s."""

    max_tv: float = 0.6
    max_rv: float = 1.0
    force: float = 2.0             # goal strength of the avoid goto along a planned path (> 1: weaker avoidance)
    reach: float = 0.25            # a point within this counts as reached
    near: float = 0.8              # a planned path this short is ended by the simple goto
    replans: int = 6               # stuck this often towards one goal: unreachable
    patience: float = 60.0         # s a moveto waits for a way blocked by what is not on the map
    retry: float = 1.0             # s between two plans round the scan while it waits
    investigate_distance: float = 1.0   # from the object's edge to the robot's centre while circling
    circle_points: int = 8
    lane: float = 2.0              # explore: distance between the lanes
    edge: float = 0.5              # explore: lanes keep this far inside the rectangle


@dataclasses.dataclass(frozen=True)
class AvoidRequest:
    """An ``avoidance/command`` request."""

    cmd_flags: int
    position: tuple[float, ...] = ()
    velocity: tuple[float, ...] = ()
    force: tuple[float, ...] = ()


@dataclasses.dataclass(frozen=True)
class Situation:
    """What a behaviour sees: the pose (x, y, theta), the recent scan points (world frame), the
    avoid goto's state for the request in force (``goto``: element[1] of a status that answers
    it, None when none has yet) and the time (s)."""

    pose: tuple[float, float, float]
    points: NDArray
    goto: int | None
    now: float


@dataclasses.dataclass(frozen=True)
class Step:
    """A behaviour's answer; ``done`` ends it (its codes stay in the status)."""

    request: AvoidRequest | None
    element2: int
    element3: int
    done: bool = False


#: The avoid request that stops the robot (cmdFlags 0, no velocity).
STOP = AvoidRequest(0, (), (0.0, 0.0))


def goto(target: Sequence[float], settings: MotionSettings, force: float = 1.0) -> AvoidRequest:
    return AvoidRequest(GOTO, (float(target[0]), float(target[1])), (settings.max_tv, settings.max_rv), (force,))


def _reached(s: Situation, target: Sequence[float], reach: float) -> bool:
    return s.goto == GOTO_REACHED or math.dist(s.pose[:2], target) <= reach


class Moveto:
    """Pluto 6.3's moveto to ``goal``: with a ``planner`` along the plan, waypoint by waypoint with
    the avoid goto, replanning when stuck; without, by ray following.  Ends with element[2] 1 at the
    goal, or 3 (ours) when the plan finds the goal unreachable.

    When what the laser sees closes every way while the map alone has one (a person standing in
    a door), the goal is not given up: the robot stops, element[2] is 4 (ours, BLOCKED), and the
    plan round the scan is tried every :attr:`MotionSettings.retry` s; the goal is unreachable
    only after :attr:`MotionSettings.patience` s of that."""

    def __init__(self, goal: Sequence[float], planner: Planner | None, settings: MotionSettings,
                 rays: RaySettings = RaySettings()) -> None:
        self.goal = (float(goal[0]), float(goal[1]))
        self.planner, self.settings, self.rays = planner, settings, rays
        self.waypoints: list[tuple[float, float]] | None = None
        self.follow = FollowSettings()
        self.follower: PathFollower | None = None
        self.progress = Progress(self.follow)
        #: On the last stretch: the simple goto to the goal (element[2] = -2).
        self.near = False
        self.stuck = 0
        self.ray: float | None = None
        self.request: AvoidRequest | None = None
        self.turning: float | None = None
        #: Why the goal is unreachable (the planner's reason), when it is.
        self.reason = ''
        #: Since when (s) what the laser sees has closed the way (None: it has not); the last try.
        self.blocked_since: float | None = None
        self.tried_at = -math.inf

    def resume(self) -> None:
        """Start again from wherever the robot is (a stop, or driven elsewhere, in between)."""
        self.waypoints, self.ray, self.turning, self.request = None, None, None, None
        self.follower, self.near = None, False
        self.blocked_since = None

    def step(self, s: Situation) -> Step:
        return self._planned(s) if self.planner is not None else self._rays(s)

    def _planned(self, s: Situation) -> Step:
        assert self.planner is not None
        follower = self.follower
        stuck = follower is not None and (
            s.goto == GOTO_STUCK and self.request is not None and self.request.cmd_flags == GOTO
            or self.progress.stuck(math.dist(s.pose[:2], self.goal) if self.near else follower.remaining(s.pose),
                                   s.now))
        if self.blocked_since is not None:
            return self._wait(s)
        if follower is None or stuck:
            planner = self.planner
            if stuck:
                self.stuck += 1
                log.info('moveto stuck (%d): replanning from %s round what the laser sees', self.stuck, s.pose[:2])
                planner = _avoiding(self.planner, s.points)
            plan = planner.plan(s.pose[:2], self.goal)
            if not plan.reachable and planner is not self.planner \
                    and self.planner.plan(s.pose[:2], self.goal).reachable:
                log.info('moveto blocked at %s by what is not on the map: waiting', s.pose[:2])
                self.blocked_since, self.tried_at, self.stuck = s.now, s.now, self.stuck - 1
                return self._stopped()
            if not plan.reachable or self.stuck > self.settings.replans:
                self.reason = plan.reason or f'stuck {self.stuck} times'
                return Step(None, UNREACHABLE, SCANNING, done=True)
            return self._follow(s.pose[:2], plan.waypoints, planner)
        distance = math.dist(s.pose[:2], self.goal)
        if self.near and (s.goto == GOTO_REACHED and self.request is not None and self.request.cmd_flags == GOTO
                          or distance <= self.settings.reach):
            return Step(None, AT_GOAL, FOLLOWING, done=True)
        if not self.near and follower.remaining(s.pose) <= self.settings.near:
            self.near, self.progress = True, Progress(self.follow)      # the simple goto now
        if self.near:
            self.request = goto(self.goal, self.settings)
            return Step(self.request, NEARING, FOLLOWING)
        heading, speed = follower.command(s.pose, self.settings.max_tv)
        self.request = AvoidRequest(FOLLOW, (0.0, heading), (speed,))
        return Step(self.request, MOVETO_SET, FOLLOWING)

    def _follow(self, start: Sequence[float], waypoints: Sequence[tuple[float, float]], planner: Planner) -> Step:
        self.follower = PathFollower(start, waypoints, self.follow, planner.grid.clearance_at)
        self.progress, self.near, self.request = Progress(self.follow), False, None
        self.waypoints = list(waypoints)
        return Step(None, MOVETO_SET, SCANNING)

    def _stopped(self) -> Step:
        self.follower, self.near, self.request = None, False, STOP
        return Step(STOP, BLOCKED, SCANNING)

    def _wait(self, s: Situation) -> Step:
        """Stopped on a blocked way: plan round the scan again every ``retry`` s; follow the first
        plan that passes, or give the goal up after ``patience`` s."""
        assert self.planner is not None and self.blocked_since is not None
        if s.now - self.tried_at < self.settings.retry:
            return self._stopped()
        self.tried_at = s.now
        planner = _avoiding(self.planner, s.points)
        plan = planner.plan(s.pose[:2], self.goal)
        if plan.reachable:
            log.info('moveto: the way is clear again after %.1f s', s.now - self.blocked_since)
            self.blocked_since = None
            return self._follow(s.pose[:2], plan.waypoints, planner)
        if s.now - self.blocked_since >= self.settings.patience:
            self.reason = f'the way stayed blocked for {s.now - self.blocked_since:.0f} s ({plan.reason})'
            return Step(None, UNREACHABLE, SCANNING, done=True)
        return self._stopped()

    def _rays(self, s: Situation) -> Step:
        if self.turning is not None:
            error = math.atan2(math.sin(self.turning - s.pose[2]), math.cos(self.turning - s.pose[2]))
            if abs(error) > math.radians(10):
                return Step(AvoidRequest(TURN, (0.0, self.turning), (0.0,)), MOVETO_SET, SCANNING)
            self.turning = None
        if self.request is not None and self.request.position == self.goal \
                and _reached(s, self.goal, self.settings.reach):
            return Step(None, AT_GOAL, FOLLOWING, done=True)
        d = decide(s.points, s.pose, self.goal, self.ray, self.rays)
        self.ray = d.ray
        if d.action is Action.TURN:
            self.turning = d.heading
            self.request = AvoidRequest(TURN, (0.0, d.heading), (0.0,))
            return Step(self.request, MOVETO_SET, SCANNING)
        if self.request is None or self.request.cmd_flags != GOTO or d.nearing \
                or math.dist(self.request.position, d.target) > 0.3:
            self.request = goto(d.target, self.settings)
        return Step(self.request, NEARING if d.nearing else MOVETO_SET, d.status)


def _avoiding(planner: Planner, points: NDArray) -> Planner:
    """A planner on ``planner``'s grid with the cells near the scan ``points`` (world frame) blocked
    too, inflated as the map's walls are: what stopped the robot is planned round."""
    if len(points) == 0:
        return planner
    tree = cKDTree(points)
    inflation = planner.grid.settings.inflation

    def free(x: NDArray, y: NDArray) -> NDArray:
        distance, _ = tree.query(np.column_stack((x.ravel(), y.ravel())), distance_upper_bound=inflation)
        return (distance > inflation).reshape(x.shape)

    return Planner(planner.grid.restricted(free), planner.settings)


def closest_object(points: NDArray, pose: Sequence[float], gap: float = 0.3) -> tuple[NDArray, float] | None:
    """The object nearest the robot among ``points`` (world frame): the chain of points less than
    ``gap`` apart that holds the nearest one; its centre and radius (m).  None: no points."""
    if len(points) == 0:
        return None
    d = np.hypot(points[:, 0] - pose[0], points[:, 1] - pose[1])
    members = np.zeros(len(points), dtype=bool)
    frontier = [int(np.argmin(d))]
    members[frontier[0]] = True
    while frontier:
        near = np.hypot(points[:, 0] - points[frontier[-1], 0], points[:, 1] - points[frontier[-1], 1]) < gap
        frontier.pop()
        new = np.nonzero(near & ~members)[0]
        members[new] = True
        frontier.extend(int(i) for i in new)
    cluster = points[members]
    centre = cluster.mean(axis=0)
    return centre, float(np.hypot(*(cluster - centre).T).max())


class Investigate:
    """Pluto 6.3's investigate: "move to closest object, unfold arm, circle the object".  No robot
    here has an arm: with a ``wrist`` the arm step is the wrist turned at the object
    (:mod:`.active_scan`, from :attr:`centre`), without one it is logged as unavailable.  element[3]
    11 approaching, 12 circling; element[2] 2 when done."""

    def __init__(self, settings: MotionSettings, inside: Callable[[float, float], bool],
                 warn: Callable[[str], object], wrist: bool = False) -> None:
        self.settings, self.inside, self.warn, self.wrist = settings, inside, warn, wrist
        self.targets: list[tuple[float, float]] | None = None
        #: The object's centre, once found.
        self.centre: tuple[float, float] | None = None
        self.approached = False
        self.request: AvoidRequest | None = None
        self.sent_at = math.inf
        self.looking_since: float | None = None

    def resume(self) -> None:
        self.targets, self.approached, self.request, self.looking_since = None, False, None, None
        self.centre = None

    def _plan(self, s: Situation) -> bool:
        found = closest_object(s.points, s.pose)
        if found is None:
            return False
        centre, radius = found
        self.centre = (float(centre[0]), float(centre[1]))
        r = radius + self.settings.investigate_distance
        start = math.atan2(s.pose[1] - centre[1], s.pose[0] - centre[0])
        n = self.settings.circle_points
        ring = [(centre[0] + r * math.cos(start + 2 * math.pi * k / n),
                 centre[1] + r * math.sin(start + 2 * math.pi * k / n))
                for k in range(n + 1)]
        self.targets = [p for p in ring if self.inside(*p)]
        return bool(self.targets)

    def step(self, s: Situation) -> Step:
        if self.targets is None and not self._plan(s):
            # No scan points yet (the module's first scans, or scans before a pose places them):
            # look for up to LOOK_S before saying there is nothing to investigate.
            self.looking_since = s.now if self.looking_since is None else self.looking_since
            if s.now - self.looking_since < LOOK_S:
                return Step(None, 0, APPROACHING)
            self.warn(f'investigate: no object in view (no scan points for {LOOK_S:.0f} s)')
            return Step(None, INVESTIGATE_DONE, APPROACHING, done=True)
        assert self.targets is not None
        if self.request is not None and (_reached(s, self.targets[0], self.settings.reach) or s.goto == GOTO_STUCK):
            self.targets.pop(0)
            self.request = None
            if not self.approached:
                self.approached = True
                self.warn('investigate: no arm on this robot; the wrist turns to the object instead' if self.wrist
                          else 'investigate: the arm step (unfold the arm) is not available on this robot')
        code = CIRCLING if self.approached else APPROACHING
        if not self.targets:
            return Step(None, INVESTIGATE_DONE, CIRCLING, done=True)
        if self.request is None:
            self.request = goto(self.targets[0], self.settings)
        return Step(self.request, 0, code)


def lawn_mower(rectangle: Rectangle, lane: float, edge: float) -> list[tuple[float, float]]:
    """Waypoints covering ``rectangle`` in lanes parallel to its base, ``lane`` apart and ``edge``
    inside its sides, alternating direction (world frame)."""
    b = max(0.0, rectangle.b - edge)
    points = []
    u, k = min(lane / 2, rectangle.h / 2), 0
    while u <= rectangle.h - min(edge, rectangle.h / 2) + 1e-9:
        ends = (-b, b) if k % 2 == 0 else (b, -b)
        points += [rectangle.world(u, v) for v in ends]
        u, k = u + lane, k + 1
    return points


class Explore:
    """Pluto 6.3's explore: cover the rectangle (a lawn mower of moveto points), then "moveto ...
    at the end of explore to find home".  Points a plan finds unreachable are skipped.  The codes
    are the current moveto's; element[2] 1 once home."""

    def __init__(self, rectangle: Rectangle, make_moveto: Callable[[tuple[float, float]], Moveto],
                 settings: MotionSettings) -> None:
        self.rectangle = rectangle
        self.points = lawn_mower(rectangle, settings.lane, settings.edge) + [(rectangle.x, rectangle.y)]
        self.make_moveto = make_moveto
        self.current: Moveto | None = None
        #: Points skipped as unreachable.
        self.skipped: list[tuple[float, float]] = []

    def resume(self) -> None:
        if self.current is not None:
            self.current.resume()

    def step(self, s: Situation) -> Step:
        while True:
            if self.current is None:
                self.current = self.make_moveto(self.points[0])
            result = self.current.step(s)
            if not result.done:
                return result
            point = self.points.pop(0)
            self.current = None
            if result.element2 == UNREACHABLE:
                self.skipped.append(point)
            if not self.points:
                return dataclasses.replace(result, request=None)
            s = dataclasses.replace(s, goto=None)
