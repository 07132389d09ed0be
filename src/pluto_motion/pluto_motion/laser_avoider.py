"""laser_avoider: WURDE's LaserAvoider (guide 7.7), an ObstacleAvoiderTransport supplier.

"This module implements a laser rangefinder-based obstacle avoidance algorithm.  It requires the
VectorMover, a source of Egomotion, and a source of RangeFinder (should be laser)" (7.7).  Consumers
use :class:`wurde_core.wrappers.ObstacleAvoider` (``stop()``, ``move_to_relative_point(p)``,
``rotate_to_relative_angle(a)``, ``info.brake``), as the guide's BlindTeleop does (1.1.5).  The
algorithm is :mod:`pluto_motion.corridor_avoid`, on the last scan and what earlier scans saw near
the robot where the laser cannot see now (:mod:`pluto_motion.scan_memory`).  It drives either the
mover (the appendix's mapping) or the mover's Navigator stream (chapter 1's mapping; goals in the
Navigator's frame: :mod:`pluto_motion.frame_link`).  docs/pluto-motion.md ("laserAvoider") has
its streams and how they are assigned.

Before changing it: a scan and the memory are placed at the odometry's pose at the scan's stamp
(:mod:`pluto_nav.pose_history`) and moved to where the robot is now, since a scan is old when it
arrives (0.2 s at 38400 baud).  It fails safe: it starts braked, and no scan for
:data:`LASER_STALE_S` (or a scan of the SICK's error values only), no odometry, or a blocked way
stop the robot (state -1 error or 4 blocked); the way is looked at again on every scan, so a
blocked robot goes on when the way clears.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

import numpy as np
from pluto_nav.continuous_odometry import ContinuousOdometry
from pluto_nav.pose_history import PoseHistory
from wurde_core import CommsManager, Logger, Point, PVector
from wurde_core.interfaces import Egomotion, NavigatorTransport, ObstacleAvoiderTransport, RangeFinder, VectorMover
from wurde_core.module_loop import run_loop, set_loop
from wurde_core.wrappers import MODE_ANGLE, MODE_POINT, MODE_STOP

from .assigned import consumer
from .corridor_avoid import AvoidSettings, Choice, choose, clearance, navigator_move, scan_to_points
from .frame_link import FrameLink
from .scan_memory import LaserView, ScanMemory, moved
from .scan_points import wrap

__all__ = ['LaserAvoider', 'main']

LOOP_S = 0.05
#: A scan older than this (s) is no scan: the robot is stopped (the SICK at 38400 baud sends one
#: every ~0.2 s).
LASER_STALE_S = 1.0
EGO_STALE_S = 0.5
#: A turn on the spot asked of a Navigator, which goes to points only, is a step this long (m):
#: more than twice the VectorMover's reach (5 cm), so that it turns to face it first.  At 0.1 m a
#: step behind the robot was, to rounding, within the mover's "just past it" rule (nearer than
#: twice the reach and more than 90 degrees off) and taken as done: the robot never moved.
NAV_TURN_STEP = 0.15
STATUS_PERIOD_S = 1.0
#: ObstacleAvoiderTransport states (see its interface description).
IDLE, MOVING, ROTATING, REACHED, BLOCKED, BRAKED, ERROR = 0, 1, 2, 3, 4, 5, -1
DEFAULT_TV, DEFAULT_RV = 0.4, 0.8
HELP = ('  -s STREAM    the ObstacleAvoiderTransport stream supplied (SimpleAvoider)\n'
        '  -L LASER     the laser stream (default: assigned to LaserClient)\n'
        '  -e EGO       the Egomotion stream (default: assigned to EgoClient)\n'
        '  -m MOVER     the VectorMoverTransport stream (default: assigned to VectorMoverClient)\n'
        '  -N NAV       the NavigatorTransport stream (default: assigned to NavClient)\n'
        '  -R RADIUS    the robot radius, m (0.35)\n'
        '  -S SAFETY    default safety distance, m (0.15)')



def _to_world(pose: tuple[float, float, float], x: float, y: float) -> tuple[float, float]:
    px, py, th = pose
    return px + x * math.cos(th) - y * math.sin(th), py + x * math.sin(th) + y * math.cos(th)


def _to_robot(pose: tuple[float, float, float], x: float, y: float) -> tuple[float, float]:
    px, py, th = pose
    dx, dy = x - px, y - py
    return dx * math.cos(th) + dy * math.sin(th), -dx * math.sin(th) + dy * math.cos(th)


class LaserAvoider:
    """The avoider's streams around :func:`pluto_motion.corridor_avoid.choose`."""

    def __init__(self, manager: CommsManager, logger: Logger, settings: AvoidSettings, *, stream: str,
                 laser: str | None = None, ego: str | None = None, mover: str | None = None,
                 nav: str | None = None) -> None:
        self.manager, self.logger, self.settings = manager, logger, settings
        self.avoider = ObstacleAvoiderTransport(stream)
        self.avoider.set_queue_mode(True)
        self.laser = consumer(RangeFinder, laser, 'LaserClient')
        self.ego = consumer(Egomotion, ego, 'EgoClient')
        self.mover = consumer(VectorMover, mover, 'VectorMoverClient')
        self.nav = consumer(NavigatorTransport, nav, 'NavClient')
        manager.register_supplier(self.avoider)
        for obj in (self.laser, self.ego, self.mover, self.nav):
            manager.register_consumer(obj)
        self.brake = True
        self.mode = MODE_STOP
        self.goal: tuple[float, float] | None = None          # Egomotion frame
        self.heading: float | None = None                     # Egomotion frame, MODE_ANGLE
        #: A relative command (x, y or angle, 0) waiting for the first pose to be fixed to.
        self.pending: tuple[float, float] | None = None
        self.limits = (DEFAULT_TV, DEFAULT_RV)
        self.safety = settings.safety
        self.state = BRAKED
        #: Odometry in one frame through restarts of the base (the goal is fixed in it).
        self.odometry = ContinuousOdometry()
        self.resets_seen = 0
        #: The Navigator's frame, measured while the robot stands (its goals are points in it).
        self.link = FrameLink()
        self.pose: tuple[float, float, float] | None = None
        self.pose_at = self.scan_at = -math.inf
        #: Odometry poses by their stamps: where the robot was when a scan was taken.
        self.history = PoseHistory()
        #: The pose the last scan was taken at (odometry frame; None until there is odometry)
        #: and its stamp.
        self.scan_pose: tuple[float, float, float] | None = None
        self.scan_stamp = -math.inf
        self.warned_stamps = False
        self.fan: tuple[float, float, float, float, float] | None = None
        self.points: np.ndarray | None = None
        #: The last scan and what earlier scans saw near the robot that it cannot see now
        #: (:mod:`pluto_motion.scan_memory`): what the avoider keeps clear of.
        self.memory = ScanMemory()
        self.view: LaserView | None = None
        self.around: np.ndarray | None = None
        self.closest = math.inf
        #: The side of the goal's bearing the way round goes by (:attr:`Choice.side`).
        self.side = 0
        self.driving = False
        self.warned_turn = False
        self.sent: tuple | None = None
        self.sent_at = -math.inf
        self._publish_info()

    # -- inputs ----------------------------------------------------------------------------------
    def _take_sensors(self, now: float) -> None:
        while self.ego.get_next_data():
            self.pose, self.pose_at = self.odometry.take(self.ego.data), now
            self.history.add(self.ego.data.timestamp.get_seconds(), self.pose)
        if self.odometry.resets != self.resets_seen:
            self.resets_seen = self.odometry.resets
            self.logger.warn(f'{self.manager.name}: the odometry started again from zero (its base '
                             f'restarted?): the goal is kept where it was; {self.odometry.describe_bridge()}')
        if self.pose is not None:
            self.link.own(self.pose, now)
        while self.nav.get_next_data():
            robot = self.nav.data.robot
            change = self.link.other((robot.x(), robot.y(), robot.theta()), now)
            if change is not None and (math.hypot(change[0], change[1]) > 0.01 or abs(change[2]) > 0.01):
                x, y, theta = self.link.transform
                self.logger.warn(f'{self.manager.name}: the odometry\'s origin is at ({x:.3f}, {y:.3f}, '
                                 f'{theta:.3f}) in the Navigator\'s frame (measured while the robot stands): '
                                 'goals go to the Navigator in its frame')
        while self.laser.get_next_info():
            i = self.laser.info
            self.fan = (float(i.theta_offset.get_value()), float(i.theta_separation.get_value()),
                        float(i.x_offset.get_value()), float(i.y_offset.get_value()),
                        float(i.max_range.get_value()))
        while self.laser.get_next_data():
            if self.fan is None:
                continue
            first, separation, x0, y0, max_range = self.fan
            ranges = list(self.laser.data.ranges)
            if ranges and all(r < 0 for r in ranges):
                continue                       # the SICK's fatal-error scan: not a scan
            self.points = scan_to_points(ranges, first, separation, x_offset=x0, y_offset=y0,
                                         max_range=max_range)
            self.scan_at = now
            self.view = LaserView(x0, y0, first, first + separation * (len(ranges) - 1), max_range)
            self.scan_stamp = self.laser.data.timestamp.get_seconds()
            self.scan_pose = self._pose_at(self.scan_stamp)
            if self.scan_pose is not None:
                self.memory.add(self.scan_pose, self.points, self.view)
        if self.points is not None and self.scan_pose is None and self.pose is not None:
            # The scan came before the first odometry: placed now that there is a pose.
            self.scan_pose = self._pose_at(self.scan_stamp)
            assert self.scan_pose is not None and self.view is not None   # a pose now; the view came with the scan
            self.memory.add(self.scan_pose, self.points, self.view)
        if self.points is not None and self.scan_pose is not None:
            assert self.pose is not None and self.view is not None        # a scan placed at a pose of the odometry
            seen = np.concatenate((self.points, self.memory.unseen(self.scan_pose, self.view)))
            self.around = moved(seen, self.scan_pose, self.pose)

    def _pose_at(self, stamp: float) -> tuple[float, float, float] | None:
        """The odometry's pose at a scan's ``stamp``; the latest pose when the odometry's stamps
        do not reach it (a scan from before the first odometry; one from another clock is said,
        once)."""
        pose = self.history.at(stamp)
        if pose is None and self.pose is not None:
            if not self.warned_stamps and self.history.beyond(stamp):
                self.logger.warn(f'{self.manager.name}: a scan stamped {stamp:.3f} is outside the '
                                 f'odometry\'s stamps ({len(self.history)} kept): scans are placed at the '
                                 'pose of their arrival until they meet')
                self.warned_stamps = True
            return self.pose
        return pose

    def _take_requests(self) -> None:
        while self.avoider.get_next_request():
            r = self.avoider.requests
            self.brake = bool(r.brake.get_value())
            self.limits = (float(r.max_trans_speed.get_value()) or DEFAULT_TV,
                           float(r.max_rot_speed.get_value()) or DEFAULT_RV)
            self.safety = float(r.safety_distance.get_value()) or self.settings.safety
            mode = int(r.mode.get_value())
            self.mode, self.goal, self.heading, self.pending = MODE_STOP, None, None, None
            self.side = 0
            goal, angle = r.goal.get_value(), float(r.angle.get_value())
            if self.brake or mode == MODE_STOP:
                pass
            elif mode == MODE_POINT and math.isfinite(goal.x()) and math.isfinite(goal.y()):
                self.mode, self.pending = mode, (goal.x(), goal.y())
            elif mode == MODE_ANGLE and math.isfinite(angle):
                self.mode, self.pending = mode, (angle, 0.0)
            else:
                self.logger.warn(f'{self.manager.name}: command refused: mode {mode}, goal '
                                 f'({goal.x()}, {goal.y()}), angle {angle}')
        if self.pending is not None and self.pose is not None:
            # A relative command is fixed in the Egomotion frame at the first pose after it came.
            if self.mode == MODE_POINT:
                self.goal = _to_world(self.pose, *self.pending)
            else:
                self.heading = wrap(self.pose[2] + self.pending[0])
            self.pending = None
            self._publish_info()

    # -- outputs ---------------------------------------------------------------------------------
    def _move(self, magnitude: float, angle: float) -> None:
        if self.mover.is_connected():
            r = self.mover.requests
            r.max_trans_speed.set_value(self.limits[0])
            r.max_rot_speed.set_value(self.limits[1])
            self.mover.move(PVector(magnitude, angle))
        if self.nav.is_connected() and self.pose is not None:
            if magnitude < 1e-3 and angle != 0.0 and not self.warned_turn:
                self.logger.warn(f'{self.manager.name}: the Navigator cannot turn on the spot; '
                                 'a turn is driven as a short step where that is free')
                self.warned_turn = True
            assert self.around is not None      # a move is only chosen from a scan (_decide)
            move = navigator_move(self.around, magnitude, angle, self.settings.radius + self.safety, NAV_TURN_STEP)
            if move is None:
                self._halt()
                return
            magnitude, angle = move
            x, y = self.link.to_other(*_to_world(self.pose, magnitude * math.cos(angle),
                                                 magnitude * math.sin(angle)))
            self.nav.requests.goal.set_value(Point(x, y))
            self.nav.requests.autonomous.set_value(True)
            self.nav.publish_request()
        self.driving = True

    def _halt(self) -> None:
        if not self.driving:
            return
        if self.mover.is_connected():
            self.mover.stop()
        if self.nav.is_connected():
            self.nav.requests.autonomous.set_value(False)
            self.nav.publish_request()
        self.driving = False

    def _publish_info(self) -> None:
        info = self.avoider.info
        info.brake.set_value(self.brake)
        info.mode.set_value(self.mode)
        info.max_trans_speed.set_value(self.limits[0])
        info.max_rot_speed.set_value(self.limits[1])
        info.safety_distance.set_value(self.safety)
        self.avoider.publish_info()

    def _publish_state(self, now: float, distance: float, angle: float) -> None:
        closest = round(self.closest, 2) if math.isfinite(self.closest) else -1.0
        value = (self.state, round(distance, 2), round(angle, 2), closest)
        if value == self.sent and now - self.sent_at < STATUS_PERIOD_S:
            return
        data = self.avoider.data
        data.state, data.distance_to_goal, data.angle_to_goal = self.state, distance, angle
        data.blocked, data.closest_obstacle = self.state == BLOCKED, closest
        self.avoider.publish_data()
        self.sent, self.sent_at = value, now

    # -- one loop --------------------------------------------------------------------------------
    def _decide(self, now: float) -> tuple[int, float, float, Choice | None]:
        """The state, distance and angle to the goal, and the move to make (None: stop)."""
        if self.brake:
            return BRAKED, 0.0, 0.0, None
        if self.mode == MODE_STOP:
            return IDLE, 0.0, 0.0, None
        if self.pending is not None or now - self.pose_at > EGO_STALE_S or now - self.scan_at > LASER_STALE_S:
            return ERROR, 0.0, 0.0, None
        # Fresh odometry and a fresh scan: the pose and what is around it are known.
        assert self.pose is not None and self.around is not None
        settings = dataclasses.replace(self.settings, safety=self.safety)
        self.closest = clearance(self.around, settings.radius)
        if self.mode == MODE_ANGLE:
            assert self.heading is not None     # fixed with the pose (no command pending)
            angle = wrap(self.heading - self.pose[2])
            if abs(angle) < 0.03:
                return REACHED, 0.0, 0.0, None
            return ROTATING, 0.0, angle, Choice(angle, 0.0, True, False, False, self.closest)
        assert self.goal is not None            # MODE_POINT, fixed with the pose (no command pending)
        gx, gy = _to_robot(self.pose, *self.goal)
        choice = choose(self.around, (gx, gy), settings, self.side, self.pose[2])
        self.side = choice.side
        distance, angle = math.hypot(gx, gy), math.atan2(gy, gx)
        if choice.reached:
            return REACHED, distance, angle, None
        if choice.blocked:
            return BLOCKED, distance, angle, None
        return MOVING, distance, angle, choice

    def step(self) -> None:
        now = time.monotonic()
        self._take_sensors(now)
        self._take_requests()
        state, distance, angle, choice = self._decide(now)
        if state != self.state:
            if state in (BLOCKED, ERROR):
                self.logger.warn(f'{self.manager.name}: stopped: '
                                 f'{"way blocked" if state == BLOCKED else "no laser scan or odometry"}')
            self.state = state
        if state == REACHED:
            self.mode, self.goal, self.heading = MODE_STOP, None, None
            self._publish_info()
        if choice is None:
            self._halt()
        else:
            self._move(choice.length, choice.heading)
        self._publish_state(now, distance, angle)

    def close(self) -> None:
        """Leave the robot stopped."""
        self._halt()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('laserAvoider')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 's:L:e:m:N:R:S:').user
    try:
        settings = AvoidSettings(radius=float(user.get('R', AvoidSettings.radius)),
                                 safety=float(user.get('S', AvoidSettings.safety)))
    except ValueError as error:
        print(f'laser_avoider: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = LaserAvoider(manager, logger, settings, stream=user.get('s', 'SimpleAvoider'),
                          laser=user.get('L'), ego=user.get('e'), mover=user.get('m'), nav=user.get('N'))
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: supplying {module.avoider.stream}; {settings}')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
