"""local_module: Pluto's localization service, localModule (Pluto 3).

It fuses the base's odometry, the DMU's filtered state, the wrist's pan and tilt and the laser's
timing stream (any subset may be missing; :mod:`.dead_reckoning` says which gives what) into the
five LocalizationPose streams of :mod:`pluto_nav.streams`, the status stream
``Localization/Status`` and the standard topics of :mod:`pluto_nav.ros_std`.  docs/navigation.md
("Navigation") gives the inputs, options, streams and status; docs/pluto-nav.md ("localModule")
the start, the resume file and the status stream's constants.

Before changing it:

- Stamps are the inputs' (the robot's clock: the odometry's, the scan's); the staleness watchdog
  (``ODOMETRY_STALE_S``) and the status rate use the wall clock (monotonic).
- Streams (1) and (4) are interpolated at the scan's time as soon as the odometry (or DMU) passes
  it, sample by sample, so that a loaded machine's backlog of odometry never trims the history
  past a scan still waiting.
- They are published only once the laser's mounting is known (its RangeFinder info, which on a
  loaded machine can come seconds after the first scans): until then the placed scans are held
  (up to ``MAX_HELD_SCANS``), never placed at the robot's centre.
- A process the MCP restarted (``wurde_core.heartbeat.restart_count() > 0``) goes on from the
  resume file (:mod:`pluto_nav.resume`, rewritten with every step's Poses); a first
  start removes it, so that a stale file cannot leak into a later restart.
"""

from __future__ import annotations

import collections
import math
import os
import pathlib
import sys
import time

import numpy as np

from wurde_core import CommsManager, Logger
from wurde_core.heartbeat import restart_count
from wurde_core.resume import state_path
from wurde_core.sender_watch import SenderWatch
from wurde_core.interfaces import ActuatorState, DMUState, Egomotion, FVectorState, LocalizationPose, RangeFinder
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_idl.errors import ConfigError

from .adjustment import Adjuster
from .dead_reckoning import RESUME_DMU_WAIT_S, DeadReckoning, DrSample
from .geometry import compose, compose_jacobians, inverse
from .odometry_model import laser_increment
from .resume import ResumeState, read_resume, write_resume
from .ros_std import LocalizationPublisher
from .start_pose import start_pose
from .streams import (DEAD_RECKONING, LASER_DEAD_RECKONING, LASER_POSE, POSE, POST_POSE, STREAMS, LocPose,
                      read_pose, write_pose)

__all__ = ['main']

LOOP_S = 0.02
#: Wall seconds without odometry after which it is called stale.
ODOMETRY_STALE_S = 1.0
#: Variance per second added to the Pose's covariance while the odometry is stale.
STALE_GROWTH = np.diag([0.1 ** 2, 0.1 ** 2, 0.05 ** 2])
#: Scan times waiting for the odometry to reach them (older ones are dropped), and scans placed
#: but held until the laser's mounting is known: bounds on memory only (minutes of scans).
MAX_PENDING_SCANS = 1000
MAX_HELD_SCANS = 1000
STATUS_PERIOD_S = 1.0
#: Wall seconds between two writes of the resume file when no new odometry came (a Pose posted,
#: the covariance growing).  With new odometry the file is written in the step that publishes it,
#: before the step's last Pose goes out (one write per step, about 0.2 ms): a restart goes on from
#: the killed process's last Pose itself.  Reckoned again from an older saved reading, the new
#: process turns the whole path driven while no localModule ran by the gap between the DMU's and
#: the odometry's turn since that reading (the DMU lags a changing turn rate by up to 0.016 rad):
#: with the file written every 0.1 s of wall time instead, a 4 s restart on a loaded machine put
#: the resumed Pose 3.1 cm off the old one's continuation.
RESUME_PERIOD_S = 0.1
HELP = ('  -m MAP    map file (start place; default map.xml in the config directory)\n'
        '  -p FILE   starting pose file "x y theta" (default: the map\'s place "start")\n'
        '  -b BASE   base module (odometry <BASE>Motion; default PlutoBase)\n'
        '  -d DMU    DMU module (default PlutoDMU)\n'
        '  -w WRIST  wrist module (default PlutoWrist)\n'
        '  -s LASER  laser module (timing <LASER>/Timing; default PlutoLaser)')


class LocalModule:
    """The localModule's state between loops; :meth:`step` is one pass of the guide's loop."""

    def __init__(self, manager: CommsManager, logger: Logger, start: tuple[float, float, float], *,
                 base: str, dmu: str, wrist: str, laser: str, resume: ResumeState | None = None,
                 resume_file: pathlib.Path | None = None) -> None:
        self.manager, self.logger = manager, logger
        self.adjuster = Adjuster()
        if resume is None:
            self.dr = DeadReckoning(start)
        else:
            self.dr = DeadReckoning(resume.dead_reckoning, start_covariance=resume.dead_reckoning_covariance,
                                    resume_odometry=(resume.odometry_stamp, resume.odometry),
                                    resume_dmu=resume.dmu)
            self.adjuster.offset = compose(resume.pose, inverse(resume.dead_reckoning))
            self.adjuster.covariance = None if resume.pose_covariance is None else resume.pose_covariance.copy()
            self.adjuster.setter, self.adjuster.holder = resume.setter, resume.holder
        self.resume_file = resume_file
        self.last_resume_wall = -np.inf
        self.resume_failed = False
        self.odometry = Egomotion(f'{base}Motion')
        self.dmu = DMUState(dmu)
        self.wrist = ActuatorState(wrist)
        self.timing = FVectorState(f'{laser}/Timing')
        self.laser = RangeFinder(laser)
        for obj in (self.odometry, self.dmu, self.timing):
            obj.set_queue_mode(True)
        self.poses = [LocalizationPose(name) for name in STREAMS]
        for obj in self.poses:
            obj.set_queue_mode(True)
            obj.set_auto_timestamp(False)
        self.status = FVectorState('Localization/Status')
        for obj in (self.odometry, self.dmu, self.wrist, self.timing, self.laser):
            manager.register_consumer(obj)
        for obj in (*self.poses, self.status):
            manager.register_supplier(obj)
        self.ros = LocalizationPublisher(manager.node)
        self.pending_scans: collections.deque[float] = collections.deque()
        #: Scans placed on the dead reckoning: (stamp, robot sample, increment since the scan
        #: before or None), published once the mounting is known.
        self.held_scans: collections.deque[tuple[float, DrSample, tuple[np.ndarray, np.ndarray] | None]] = (
            collections.deque(maxlen=MAX_HELD_SCANS))
        self.last_scan_stamp: float | None = None
        self.pan = self.tilt = 0.0
        self.mount_z = 0.0
        self.mount_known = False              # the laser's RangeFinder info has come
        self.tv = self.rv = 0.0
        self.last_odometry_wall = -np.inf      # fresh only once odometry came

        self.last_dmu_wall = -np.inf
        self.last_status_wall = -np.inf
        self.stale = True                     # no odometry yet
        self.resets_seen = 0
        self.dmu_wait_said = False
        #: A resumed process says its first step (the motion while no localModule ran) once.
        self.resumed_step_said = resume is None
        # Who sends the DMU's and the base's messages: a new process starts its count again
        # (wurde_core.sender_watch); a base or DMU restarted while this module was down is told
        # from the one it last heard by what its resume state saved.
        self.dmu_sender = SenderWatch() if resume is None or resume.dmu is None else SenderWatch(
            resume.dmu_session, resume.dmu_sequence)
        self.odometry_sender = SenderWatch() if resume is None else SenderWatch(
            resume.odometry_session, resume.odometry_sequence)
        self._publish_start(start, resume)

    def _publish_start(self, start: tuple[float, float, float], resume: ResumeState | None) -> None:
        value = LocPose(pose=(start[0], start[1], 0.0, start[2], 0.0, 0.0))
        for index, obj in enumerate(self.poses):
            if resume is not None:      # (0), (1): dead reckoning; (2) to (4): adjusted, the setter
                dead = index in (DEAD_RECKONING, LASER_DEAD_RECKONING)
                xyt = resume.dead_reckoning if dead else resume.pose
                value = LocPose(pose=(xyt[0], xyt[1], 0.0, xyt[2], 0.0, 0.0),
                                setter=0 if dead else resume.setter)
            write_pose(obj.info, value)
            obj.publish_info()

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        self._take_mounting()
        while self.wrist.get_next_data():
            position = list(self.wrist.data.position)
            if len(position) >= 2:
                self.pan, self.tilt = float(position[0]), float(position[1])
        while self.timing.get_next_data():
            self.pending_scans.append(self.timing.data.timestamp.get_seconds())
            while len(self.pending_scans) > MAX_PENDING_SCANS:
                self.pending_scans.popleft()
        completed: list[DrSample] = []
        while self.dmu.get_next_data():
            d = self.dmu.data
            self.last_dmu_wall = time.monotonic()
            restarted = self.dmu_sender.take(d.ros_message().header)      # a new DMU process
            completed += self.dr.add_dmu(d.timestamp.get_seconds(), d.theta, d.phi, d.psi, restarted=restarted)
            self._place_scans()
        while self.odometry.get_next_data():
            d = self.odometry.data
            self.last_odometry_wall = time.monotonic()
            self.tv, self.rv = d.tv, d.rv
            location = d.location
            # A new base process's odometry starts again from zero however long it was down (too
            # slow a jump for the speed rule to see).
            restarted = self.odometry_sender.take(d.ros_message().header)
            completed += self.dr.add_odometry(d.timestamp.get_seconds(), location.x(), location.y(),
                                              location.theta(), restarted=restarted)
            self._place_scans()
        if self.dr.dmu_not_come and not self.dmu_wait_said:
            self.dmu_wait_said = True
            self.logger.warn(f'{self.manager.name}: resumed without the DMU: none of its samples came within '
                             f'{RESUME_DMU_WAIT_S:g} s, so the turn while no localModule ran is the odometry\'s')
        if self.dr.odometry_resets != self.resets_seen:
            self.resets_seen = self.dr.odometry_resets
            self.logger.warn(f'{self.manager.name}: the odometry jumped (its base restarted?): taken as no '
                             f'motion ({self.resets_seen} so far)')
        for index, sample in enumerate(completed):
            self.adjuster.on_step(sample)
            if not self.resumed_step_said:
                self._say_resumed_step(sample)
            if index == len(completed) - 1:
                self.save_resume(force=True)    # a Pose published is a Pose saved
            self._publish_robot(sample)
        self._place_scans()          # scans timed before odometry already here
        self._publish_scans()
        posts = self.poses[POST_POSE]
        while posts.get_next_request():
            self._post(posts.requests)
        self._watch_odometry()
        self.save_resume()

    def _say_resumed_step(self, sample: DrSample) -> None:
        """Log a resumed process's first Pose: the saved one advanced by the motion since its
        reading.  Its subscribers may not hear the first Poses of a new process (discovery), so
        the log is where that step can be checked."""
        self.resumed_step_said = True
        x, y, theta = self.adjuster.pose(sample)
        turn = 'the DMU' if sample.dmu_used else 'the odometry'
        self.logger.notice(f'{self.manager.name}: first Pose since the restart: x={x:.4f} y={y:.4f} '
                         f'theta={theta:.4f} at odometry stamp {sample.stamp:.6f}; '
                         f'{math.hypot(*sample.increment[:2]):.3f} m and {sample.increment[2]:.3f} rad '
                         f'since the saved reading (the turn by {turn})')

    def save_resume(self, force: bool = False) -> None:
        """Rewrite the resume file (at most every ``RESUME_PERIOD_S`` unless ``force``: new Poses)."""
        now = time.monotonic()
        if self.resume_file is None or (not force and now - self.last_resume_wall < RESUME_PERIOD_S):
            return
        latest, odometry = self.dr.latest, self.dr.latest_odometry
        if latest is None or odometry is None:
            return      # no odometry yet: a resume file from before (if any) still holds
        self.last_resume_wall = now
        state = ResumeState(odometry_stamp=odometry[0], odometry=tuple(odometry[1]),
                            dead_reckoning=tuple(latest.pose), dead_reckoning_covariance=latest.covariance,
                            pose=tuple(self.adjuster.pose(latest)),
                            pose_covariance=self.adjuster.covariance, setter=self.adjuster.setter,
                            holder=self.adjuster.holder, odometry_sequence=self.odometry_sender.sequence,
                            odometry_session=self.odometry_sender.session, dmu=self.dr.dmu_at(latest.stamp),
                            dmu_session=self.dmu_sender.session, dmu_sequence=self.dmu_sender.sequence)
        try:
            write_resume(self.resume_file, state)
        except OSError as error:
            if not self.resume_failed:
                self.resume_failed = True
                self.logger.error(f'{self.manager.name}: cannot write the resume file {self.resume_file}: '
                                  f'{error.strerror or error} (a restart will not know where the robot '
                                  f'is; logged once)')

    def _take_mounting(self) -> None:
        while self.laser.get_next_info():
            info = self.laser.info
            self.adjuster.mount = np.array([info.x_offset.get_value(), info.y_offset.get_value(), 0.0])
            self.mount_z = float(info.z_offset.get_value())
            self.mount_known = True

    def _publish_robot(self, sample: DrSample) -> None:
        setter = self.adjuster.setter
        pose = self.adjuster.pose(sample)
        cov = self.adjuster.pose_covariance(sample)
        for index, xyt, covariance, flags in ((DEAD_RECKONING, sample.pose, sample.covariance, 0),
                                              (POSE, pose, cov, setter)):
            value = LocPose(pose=(xyt[0], xyt[1], 0.0, xyt[2], sample.phi, sample.psi), pan=self.pan,
                            tilt=self.tilt, covariance=covariance, setter=flags, stamp=sample.stamp)
            write_pose(self.poses[index].data, value)
            self.poses[index].publish_data()
        self.ros.publish(sample.stamp, sample.pose, sample.covariance, self.tv, self.rv,
                         self.adjuster.offset, pose, cov)

    def _place_scans(self) -> None:
        """The robot at each waiting scan's time that the dead reckoning has now passed."""
        latest = self.dr.latest
        while self.pending_scans and latest is not None and self.pending_scans[0] <= latest.stamp:
            stamp = self.pending_scans.popleft()
            robot = self.dr.at(stamp)
            if robot is None:      # older than the history: nothing to interpolate
                continue
            since = self.dr.increment_since_start(stamp) if self.last_scan_stamp is None \
                else self.dr.increment_between(self.last_scan_stamp, stamp)
            self.last_scan_stamp = stamp
            self.held_scans.append((stamp, robot, since))

    def _publish_scans(self) -> None:
        if not self.mount_known:
            return      # where the laser is on the robot is not known yet (a loaded machine's
            #             first scans came before the laser's info: SLAM's map was 0.2 m off)
        while self.held_scans:
            stamp, robot, since = self.held_scans.popleft()
            laser = self.adjuster.laser(robot.pose)
            increment_cov = np.zeros((3, 3)) if since is None else laser_increment(*since, self.adjuster.mount)[1]
            setter = self.adjuster.setter
            adjusted = compose(self.adjuster.offset, laser)
            for index, xyt, cov, flags in ((LASER_DEAD_RECKONING, laser, increment_cov, 0),
                                           (LASER_POSE, adjusted, self._laser_abs_cov(robot), setter)):
                value = LocPose(pose=(xyt[0], xyt[1], self.mount_z, xyt[2], robot.phi, robot.psi),
                                pan=self.pan, tilt=self.tilt, covariance=cov, setter=flags, stamp=stamp)
                write_pose(self.poses[index].data, value)
                self.poses[index].publish_data()

    def _laser_abs_cov(self, robot: DrSample) -> np.ndarray:
        cov = self.adjuster.pose_covariance(robot)
        j_robot, _ = compose_jacobians(self.adjuster.pose(robot), self.adjuster.mount)
        return j_robot @ cov @ j_robot.T

    def _post(self, request: object) -> None:
        value = read_pose(request)
        source = getattr(request, 'source', '') or ''
        refusal = self.adjuster.write(value, source, self.dr)
        if refusal is not None:
            self.logger.warn(f'{self.manager.name}: Post_Pose from {source or "?"} with setter {value.setter} '
                             f'refused: {refusal.reason}')
            self._publish_status(force=True)
            return
        posts = self.poses[POST_POSE]
        value.setter = self.adjuster.setter
        write_pose(posts.data, value)
        posts.publish_data()
        write_pose(posts.info, value)      # info is kept: a late reader learns the setter at once
        posts.publish_info()
        self._publish_status(force=True)

    def _watch_odometry(self) -> None:
        now = time.monotonic()
        stale = now - self.last_odometry_wall > ODOMETRY_STALE_S
        if stale and self.dr.latest is not None:
            latest = self.dr.latest
            if self.adjuster.covariance is None:
                self.adjuster.covariance = latest.covariance.copy()
            self.adjuster.grow(STALE_GROWTH * LOOP_S)
            if now - self.last_status_wall >= STATUS_PERIOD_S:
                self._publish_robot(latest)
        if stale != self.stale:
            self.stale = stale
            self.logger.warn(f'{self.manager.name}: odometry {"stopped" if stale else "flowing"}')
            self._publish_status(force=True)
        self._publish_status()

    def _publish_status(self, force: bool = False) -> None:
        now = time.monotonic()
        if not force and now - self.last_status_wall < STATUS_PERIOD_S:
            return
        self.last_status_wall = now
        latest = self.dr.latest
        cov = self.adjuster.pose_covariance(latest) if latest is not None else np.zeros((3, 3))
        dmu_fresh = now - self.last_dmu_wall <= ODOMETRY_STALE_S
        data = self.status.data
        data.element = [0 if self.stale else 1, 1 if dmu_fresh else 0, self.adjuster.setter,
                        len(self.adjuster.refusals)]
        data.data = [now - self.last_odometry_wall, float(np.sqrt(max(cov[0, 0] + cov[1, 1], 0.0)))]
        self.status.publish_data()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('localModule')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'm:p:b:d:w:s:').user
    map_file = config_file(manager, opts.get('m'), 'map.xml')
    default_missing = 'm' not in opts and not os.path.exists(map_file)
    try:
        start = start_pose(opts.get('p') and config_file(manager, opts['p'], ''),
                           None if default_missing else map_file)
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    resume_file = state_path()
    resume, why = _resume_state(logger, manager.name, resume_file)
    if resume is None and default_missing and 'p' not in opts:
        logger.warn(f'{manager.name}: no map {map_file} and no pose file: starting at the origin')
    module = LocalModule(manager, logger, start, base=opts.get('b', 'PlutoBase'), dmu=opts.get('d', 'PlutoDMU'),
                         wrist=opts.get('w', 'PlutoWrist'), laser=opts.get('s', 'PlutoLaser'), resume=resume,
                         resume_file=resume_file)
    set_loop(manager, LOOP_S)
    if resume is not None:
        x, y, theta = resume.pose
        logger.notice(f'{manager.name}: resuming at x={x:.3f} y={y:.3f} theta={theta:.3f} (setter '
                      f'{resume.setter}) from {resume_file}, odometry stamp {resume.odometry_stamp:.3f}: {why}')
    else:
        origin = 'the pose file' if 'p' in opts else 'the origin' if default_missing else f'the map {map_file}'
        logger.notice(f'{manager.name}: starting at x={start[0]:.3f} y={start[1]:.3f} theta={start[2]:.3f} '
                      f'from {origin}: {why}')
    return run_loop(manager, module.step, lambda: module.save_resume(force=True))


def _resume_state(logger: Logger, name: str, path: pathlib.Path | None) -> tuple[ResumeState | None, str]:
    """The state to resume (None: start as configured) and why."""
    if path is None:
        return None, 'not started by an MCP (no state file)'
    count = restart_count()
    if count == 0:
        try:
            path.unlink()
        except FileNotFoundError:
            pass
        except OSError as error:
            logger.warn(f'{name}: cannot remove the old resume file {path}: {error.strerror or error}')
        return None, 'a first start (the MCP has not started it before)'
    state, reason = read_resume(path)
    if state is None:
        logger.warn(f'{name}: restart {count}, but the resume file {path} is unusable ({reason}): '
                    f'starting as configured; where the robot is, is lost')
        return None, f'restart {count} without a usable resume file'
    return state, f'restart {count}'


if __name__ == '__main__':
    sys.exit(main())
