"""motion_module: Pluto's motionModule (Pluto 6.3), the top link of the movement chain (Pluto 4).

It reads ``motion/command`` (ActuatorState requests: 42 moveto, 43 investigate, 44 explore, 45
resume, 46 the rectangle; 0..39 are passed down) and writes ``avoidance/command`` requests
through :class:`~pluto_motion.avoid_proxy.AvoidProxy`, reading ``avoidance/status``, the laser
(``-s LASER``) and the pose (:class:`pluto_motion.pose_source.PoseSource`: Localization/Pose, else
Dead-Reckoning, else the base odometry; each fall-back warned once).  The control is
:mod:`pluto_motion.motion_control`, the commands are parsed by :mod:`pluto_motion.motion_command`.
With a map (``-m``) a moveto is planned and followed; without one, or with ``-R`` (Pluto 6.3's
"42 moveto using ray_following"), it is ray following.  The wrist (``-W``) is turned for active
scanning (Pluto 4; :mod:`pluto_motion.active_scan`); without a wrist nothing is sent.

docs/movement.md ("Movement", motionModule) has the tables of ``motion/command`` and ``motion/status``
and the active scanning; ``-h`` lists the options; the tunables (:data:`TUNABLES`, ROS 2
parameters starting from the options) are taken by the next motion command.

Before changing it: a plan on a large map takes seconds of CPU during which the loop does not
beat, hence the longer heartbeat TTL :data:`PLANNING_TTL_S`; and everything sent down goes through
the AvoidProxy, which resends a request until the avoidModule echoes it.
"""

from __future__ import annotations

import collections
import math
import sys
import time

import numpy as np
from wurde_core import CommsManager, Logger
from wurde_core.interfaces import ActuatorState, FVectorState, RangeFinder
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_core.parameters import TunedSettings, out_of_range
from wurde_core.resume import ResumeState
from wurde_idl.errors import ConfigError

from .avoid_proxy import AvoidProxy
from .motion_behaviours import AvoidRequest, MotionSettings
from .plan_topic import PlanPublisher
from .motion_command import COMMAND, STATUS, THREAD_STOPPED, CommandRefused, MotionCommand, parse_command
from .motion_control import MotionController
from .motion_resume import restore, state_of
from .planning_grid import PlanningGrid, grid_from_map_file
from .pose_source import PoseSource
from .ray_follow import ScanGeometry, geometry_from_info, scan_points
from .wrist_link import WristLink

__all__ = ['MotionModule', 'main']
LOOP_S = 0.05
STATUS_PERIOD_S = 1.0
#: Heartbeat TTL (s): a plan on a large map (a million cells, and a replan round what the laser
#: saw builds its graph again) takes seconds of CPU on a loaded machine, during which the loop does
#: not beat; with the usual 1 s the MCP would take the busy module for hung after 4 s and kill it,
#: losing the moveto.
PLANNING_TTL_S = 5.0
#: Scans whose points the ray following and investigate decide on (the laser sees 180 degrees).
RECENT_SCANS = 8
#: The motion settings a user may tune while it runs; a motion command takes them when it starts.
TUNABLES: dict[str, tuple[str, float | None, float | None]] = {
    'max_tv': ('linear speed of the avoid goto, m/s', 0.05, 2.0),
    'max_rv': ('angular speed of the avoid goto, rad/s', 0.05, 3.0),
    'reach': ('a point within this is reached, m', 0.05, 2.0),
    'near': ('a planned path this short is ended by the simple goto, m', 0.1, 5.0),
    'investigate_distance': ('investigate: from the object\'s edge to the robot\'s centre, m', 0.3, 5.0),
    'lane': ('explore: distance between the lanes, m', 0.3, 10.0),
    'edge': ('explore: the lanes keep this far inside the rectangle, m', 0.0, 5.0)}
HELP = ('  -m MAP       plan moveto on this map (config/maps format); without: ray following\n'
        '  -R           moveto by ray following even with -m (Pluto 6.3)\n'
        '  -s LASER     the laser module (default PlutoLaser)\n'
        '  -b BASE      the base, for its odometry when no localModule runs and no map is given (PlutoBase)\n'
        '  -W WRIST     the wrist turned for active scanning (default PlutoWrist; none there: not turned)\n'
        '  -v MAX_TV    linear speed of the avoid goto, m/s (0.6)\n'
        '  -w MAX_RV    angular speed of the avoid goto, rad/s (1.0)')


class MotionModule:
    """The motionModule's streams around a :class:`MotionController`."""

    def __init__(self, manager: CommsManager, logger: Logger, grid: PlanningGrid | None,
                 settings: MotionSettings, *, laser: str, base: str = 'PlutoBase', wrist: str = 'PlutoWrist',
                 rays_only: bool = False) -> None:
        self.manager, self.logger = manager, logger
        self.control = MotionController(grid, settings, warn=self._warn, rays_only=rays_only)
        self.tuned = TunedSettings(manager, settings, TUNABLES)
        self.commands = ActuatorState(COMMAND)
        self.commands.set_queue_mode(True)
        self.status = FVectorState(STATUS)
        #: The link below, through the proxy every program uses: a request waits until the
        #: avoidModule's reader is matched and goes again until echoed (on a loaded machine a
        #: request sent once can be lost between discovery's two directions).
        self.avoid = AvoidProxy(manager)
        self.laser = RangeFinder(laser)
        for obj in (self.commands, self.status):
            manager.register_supplier(obj)
        manager.register_consumer(self.laser)
        self.poses = PoseSource(manager, base, self._warn, user='moveto and explore steer',
                                localization_only=grid is not None)
        self.geometry: ScanGeometry | None = None
        self.recent: collections.deque = collections.deque(maxlen=RECENT_SCANS)
        self.avoid_data: list[float] = [0.0, 0.0]
        self.avoid_element: list[int] = [0, 0]
        self.refused = 0
        self.sent_status: tuple | None = None
        self.status_at = -math.inf
        self.plan = PlanPublisher(manager.node)
        self.wrist = WristLink(manager, wrist, log=lambda text: logger.notice(f'{manager.name}: {text}'),
                               trace=lambda text: logger.debug(f'{manager.name}: {text}'))
        self.resume = ResumeState()
        self.kept: dict | None = None
        state, why = self.resume.load()
        if state is not None:
            resumed = restore(self.control, state)
            if self.control.running:
                self.avoid.start_activity()                      # the avoid thread with it
            self.logger.notice(f'{manager.name}: resuming {resumed} ({why})')

    def _warn(self, text: str) -> None:
        self.logger.warn(f'{self.manager.name}: {text}')

    # -- inputs ----------------------------------------------------------------------------------
    def _take_laser(self, pose: tuple[float, float, float] | None) -> None:
        if self.laser.get_next_info():
            self.geometry = geometry_from_info(self.laser.info)
        if self.laser.get_next_data() and self.geometry is not None and pose is not None:
            # Placed where the robot was when the scan was taken (0.2 s before it arrives at 38400
            # baud), by the pose source in use; where the robot is when the stamp is not kept.
            source, stamp = self.poses.source, self.laser.data.timestamp.get_seconds()
            taken = self.poses.pose_at(source, stamp) if source is not None else None
            self.recent.append(scan_points(list(self.laser.data.ranges), taken or pose, self.geometry))

    def _take_commands(self, pose: tuple[float, float, float] | None) -> None:
        while self.commands.get_next_request():
            r = self.commands.requests
            flags = int(r.cmd_flags.get_value())
            try:
                command = parse_command(flags, list(r.position.get_value()), list(r.velocity.get_value()),
                                        list(r.force.get_value()))
                requests = self.control.accept(command, pose)
            except CommandRefused as error:
                self.refused += 1
                self._warn(f'refused command ({self.refused} so far): {error}')
                continue
            self._echo(command)
            for request in requests:
                self._send(request)
        while self.status.get_next_request():
            element = list(self.status.requests.element.get_value())
            if element and element[0] == 0:
                self.control.start()
                self.avoid.start_activity()                      # starting motion starts avoid
                self.logger.notice(f'{self.manager.name}: start_activity')
            elif element and element[0] == THREAD_STOPPED:
                self.control.running = False                     # avoid goes on (Pluto 6.3)
                self.control.behaviour = None
                self.logger.notice(f'{self.manager.name}: thread stopped by request')

    def _take_avoid(self) -> int | None:
        state = None
        for message in self.avoid.update():
            self.avoid_data = [float(v) for v in message.data][:2]
            self.avoid_element = [int(v) for v in message.element][:2]
            if len(self.avoid_element) > 1:
                state = self.avoid_element[1]
        return state if state is not None else (self.avoid_element[1] if len(self.avoid_element) > 1 else None)

    # -- outputs ---------------------------------------------------------------------------------
    def _send(self, request: AvoidRequest) -> None:
        self.avoid.send(request.cmd_flags, list(request.velocity), list(request.position), list(request.force))

    def _echo(self, command: MotionCommand) -> None:
        """The command accepted, on the data channel of ``motion/command`` (the proxy's handshake)."""
        data = self.commands.data
        data.cmd_flags = command.cmd_flags
        data.position, data.velocity, data.force = list(command.position), list(command.velocity), list(command.force)
        self.commands.publish_data()

    def _publish_status(self, now: float) -> None:
        element = (self.avoid_element + [0, 0])[:2] + [self.control.element2, self.control.element3]
        data = (self.avoid_data + [0.0, 0.0])[:2] + [float(self.refused)]
        value = ([float(v) for v in data], [int(v) for v in element])
        if value == self.sent_status and now - self.status_at < STATUS_PERIOD_S:
            return
        self.status.data.data, self.status.data.element = value
        self.status.publish_data()
        self.sent_status, self.status_at = value, now

    def step(self) -> None:
        now = time.monotonic()
        self.control.settings = self.tuned.current()
        pose = self.poses.pose()
        self._take_laser(pose)
        self._take_commands(pose)
        goto_state = self._take_avoid()
        points = np.vstack(list(self.recent)) if self.recent else np.zeros((0, 2))
        for request in self.control.step(pose, points, goto_state, now):
            self._send(request)
        self.plan.update(self.control.behaviour, self.manager.node.get_clock().now().to_msg())
        self.control.wrist = self.wrist.present
        self.wrist.update(self.control.aim(pose, now), now)
        self._publish_status(now)
        kept = state_of(self.control)
        if kept != self.kept and self.resume.save(kept, force=True):
            self.kept = kept


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('motionModule')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'm:s:b:v:w:W:R').user
    grid = None
    try:
        settings = MotionSettings(max_tv=float(user.get('v', 0.6)), max_rv=float(user.get('w', 1.0)))
        problem = out_of_range(settings, TUNABLES)
        if problem is not None:
            raise ValueError(problem)
    except ValueError as error:
        print(f'motion_module: -v/-w: {error}', file=sys.stderr, flush=True)
        return 2
    if 'm' in user:
        map_file = config_file(manager, user['m'], 'map.xml')
        try:
            grid = grid_from_map_file(map_file)
        except ConfigError as error:
            return exit_on_config_error(argv[0], error)
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = MotionModule(manager, logger, grid, settings, laser=user.get('s', 'PlutoLaser'),
                          base=user.get('b', 'PlutoBase'), wrist=user.get('W', 'PlutoWrist'), rays_only='R' in user)
    set_loop(manager, LOOP_S, PLANNING_TTL_S)
    if grid is None:
        how = 'no map: ray following'
    elif 'R' in user:
        how = f'map {user["m"]} for the pose; moveto by ray following (-R)'
    else:
        how = f'planning on {user["m"]} ({grid.shape[1]} x {grid.shape[0]} cells of {grid.resolution} m)'
    logger.notice(f'{manager.name}: {how}')
    return run_loop(manager, module.step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
