"""dummy_base: Pluto's dummy base server (5), driving a simulated robot through a map.

It supplies exactly the streams of a real base (see :mod:`wurde_drivers.streams.base`), plus the
ground truth on ``<name>Truth`` (Egomotion, every simulation step) for the other dummies, tests and
plots, mirrored on ``/<name>/ground_truth/odom`` (:func:`wurde_drivers.ros_std.ground_truth_publisher`).
Its module name (``-n``) should be the config's base name, since the other dummies follow
``<base name>Truth``.

Simulated time advances in the config's fixed steps, catching up with the wall clock times the
time scale, and goes out on ``/clock`` (:mod:`wurde_drivers.sim.dummies.clock_topic`); the command
watchdog counts simulated time.  The config's people (:mod:`wurde_drivers.sim.people`) are in the
world: the sonars see them, the robot stops at them, and one that walks into the robot presses a
bumper and stops the base.

The simulated robot outlives its driver, as a real one does: under an MCP the base keeps where
the robot truly stands in its state file (:mod:`wurde_core.resume`), and a restarted base puts
the robot back there.  docs/wurde-drivers.md ("sim.dummies.base") has the detail.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

from wurde_core import CommsManager, Logger, Pose, RunState, Time
from wurde_core.interfaces import Egomotion
from wurde_core.resume import ResumeState
from wurde_idl.errors import ConfigError

from ...module_setup import exit_on_config_error, set_loop
from ...ros_std import OdometryPublisher, ground_truth_publisher
from ...ros_std_covariance import OdometryCovariance
from ...streams.base import BaseLimits, BaseStreams
from ..clock import SimClock, make_rng
from .clock_topic import ClockPublisher
from .people_topic import PeoplePublisher
from ..loading import load_sim, sim_config_path
from ..robot import SimRobot

#: Most simulation steps one loop may run before it gives up catching up (and says so).
MAX_CATCH_UP = 200
#: Wall seconds between loops.
LOOP_S = 0.01
#: Longest (simulated) time the base is given to come to rest when it goes Idle.
MAX_STOP_S = 10.0


def _every(rate: float, step: float) -> int:
    return max(1, round(1.0 / (rate * step)))


def main(argv: list[str] | None = None) -> int:
    """The ``dummy_base`` program: the simulated base of sim-config.xml.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoBase')
    path = sim_config_path(manager, argv)
    kept = ResumeState()
    resumed, why = _resumed(kept)
    try:
        config, world, start = load_sim(path)
        start = resumed or start
        robot = SimRobot(world, config.robot, make_rng(config.seed, 'base'), start=start)
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        return exit_on_config_error(argv[0], ConfigError(path, None, str(error)))
    logger = Logger(manager.name)
    spec = config.robot
    limits = BaseLimits(spec.limits.max_tv, spec.limits.max_rv, spec.limits.tv_accel, spec.limits.rv_accel,
                        wheel_base=2 * spec.bumpers.radius)
    noise = spec.odometry_noise   # the simulator's own error model is the covariance's source
    streams = BaseStreams(manager.name, synchro=config.base.synchro, limits=limits,
                          command_timeout=config.base.command_timeout, logger=logger,
                          odometry=OdometryCovariance(trans=noise.trans, rot=noise.rot, drift=noise.drift))
    truth = Egomotion(f'{manager.name}Truth')
    truth.set_queue_mode(True)
    streams.register(manager)
    manager.register_supplier(truth)
    truth_std = ground_truth_publisher(manager.node, manager.name)
    manager.register_supplier(logger)
    set_loop(manager, LOOP_S)

    clock = SimClock(step_s=config.step, time_scale=config.time_scale, start=time.time())
    robot.now = clock.now
    clock_topic = ClockPublisher(manager.node)
    people_topic = PeoplePublisher(manager.node, manager.name, world.people) if len(world.people) else None
    streams.publish_all_info()
    streams.publish_sonar_info(count=spec.sonar.count, max_range=spec.sonar.max_range,
                               half_angle=spec.sonar.half_angle, radius=spec.sonar.radius, z=spec.sonar.mount_z)
    streams.publish_bumper_info(spec.bumpers.radius)
    b = robot.battery
    streams.publish_power_info(b.nominal_voltage, b.low_voltage, b.critical_voltage, b.capacity_j)
    truth.info.origin.set_value(Pose(0.0, 0.0, 0.0))
    truth.publish_info()
    odometry_every = _every(config.base.rate, config.step)
    sonar_every = _every(config.base.sonar_rate, config.step)
    power_every = _every(1.0, config.step)
    origin = 'resumed' if resumed else 'the start of the config'
    logger.notice(f'dummy base in {world.name} at {start} ({origin}: {why}), seed {config.seed}, '
                  f'time scale {config.time_scale}')
    for person in world.people:
        walk = person.walk
        logger.notice(f'person "{person.name}": {person.body.describe()}, {walk.speed:g} m/s, '
                      f'{len(walk.points)} points ({walk.mode}), a round every {walk.cycle:.1f} s')
    wall0 = time.monotonic()
    last_bumpers = robot.bumpers

    def target_step() -> int:
        return int((time.monotonic() - wall0) * config.time_scale / config.step)

    def brake_for_idle() -> None:
        """Idle (guide 5.2.1): the base must not drive on unattended; bring it to rest now."""
        streams.stop()
        robot.command(0.0, 0.0)
        for _ in range(int(MAX_STOP_S / config.step)):
            if robot.truth.tv == 0.0 and robot.truth.rv == 0.0:
                break
            _advance(robot, clock)

    def resume() -> None:
        """Back in Run: the robot stood still while Idle; simulated time jumps to the wall's."""
        clock.steps = max(clock.steps, target_step())

    manager.on_state(RunState.IDLE, brake_for_idle)
    manager.on_state(RunState.RUN, resume)
    while manager.run_update() == RunState.RUN:
        target = target_step()
        if target - clock.steps > MAX_CATCH_UP:
            logger.warn(f'{manager.name}: {target - clock.steps} steps behind; dropping them')
            wall0 = time.monotonic() - clock.steps * config.step / config.time_scale
            target = clock.steps + 1
        while clock.steps < target:
            command = streams.take_command(clock.elapsed)
            if command is not None:
                robot.spec = dataclasses.replace(robot.spec, limits=dataclasses.replace(
                    robot.spec.limits, tv_accel=command.tv_accel, rv_accel=command.rv_accel))
                robot.command(command.tv, command.rv)
            _advance(robot, clock)
            for index in robot.new_person_contacts:
                side = ' and '.join(name for name, on in zip(('front', 'back'), robot.bumpers) if on)
                logger.warn(f'person "{world.people[index].name}" touched the robot '
                            f'(bumper {side or "none"}); contact {robot.person_contacts} with people')
            if robot.bumper_stop and (streams.current.tv or streams.current.rv):
                streams.current = dataclasses.replace(streams.current, tv=0.0, rv=0.0)
                streams.publish_drive_info()
                logger.warn(f'{manager.name}: bumper {"front" if robot.bumpers[0] else "back"} '
                            'pressed: stopped')
            _publish(truth, truth_std, robot.truth, clock.now)
            clock_topic.publish(clock.now)
            n = clock.steps
            if n % odometry_every == 0:
                o = robot.odometry
                streams.publish_motion(o.x, o.y, o.theta, o.tv, o.rv, o.acceleration, clock.now)
                # The pose to restart at is the truth of the odometry just published (after it:
                # killed in between, the message may not have left either).  Consumers bridge a
                # restart on the assumption that the robot stood since their last sample
                # (pluto_nav.continuous_odometry); a pose saved on a clock of its own was up to a
                # save period and an odometry period away from that sample, and a robot turning at
                # 1 rad/s came back 0.066 rad off its odometry: 0.3 m off after 4 m.  The robot is
                # taken to stop the moment its driver stops reporting (a real base coasts on until
                # its watchdog stops it, which nothing but a localiser could bridge).
                if not kept.save({'x': robot.truth.x, 'y': robot.truth.y, 'theta': robot.truth.theta},
                                 force=True) and kept.failure:
                    logger.warn(f'{manager.name}: {kept.failure}; the robot would restart at the start')
                    kept.path = None
            if n % odometry_every == 0 and people_topic is not None:
                people_topic.publish(clock.now)
            if n % odometry_every == 0 or robot.bumpers != last_bumpers:
                streams.publish_bumpers(robot.bumpers, clock.now)
                last_bumpers = robot.bumpers
            if n % sonar_every == 0:
                streams.publish_sonar(robot.sonar(), clock.now)
            if n % power_every == 0:
                streams.publish_power(voltage=b.voltage, current=b.current, power=b.power_w, charge=b.charge,
                                      energy=b.energy_j, low=b.low_voltage, critical=b.critical_voltage,
                                      stamp=clock.now)
    if len(world.people):
        logger.notice(f'{robot.person_contacts} contacts with people')
    manager.clean_up(exiting=True)
    return 0


def _advance(robot: SimRobot, clock: SimClock) -> None:
    """One simulation step: the clock's, and the robot's to the clock's new stamp (the people's
    positions are a function of it)."""
    dt = clock.tick()
    robot.step(dt, now=clock.now)


def _resumed(kept: ResumeState) -> tuple[tuple[float, float, float] | None, str]:
    """Where the last process of this base left the robot, if this is its restart by the MCP."""
    saved, why = kept.load()
    if saved is None:
        return None, why
    try:
        pose = (float(saved['x']), float(saved['y']), float(saved['theta']))
    except (KeyError, TypeError, ValueError) as error:
        return None, f'{kept.path}: no pose in the saved state ({error!r})'
    if not all(math.isfinite(v) for v in pose):
        return None, f'{kept.path}: the saved pose is not finite'
    return pose, why


def _publish(truth: Egomotion, standard: OdometryPublisher, state: object, stamp: float) -> None:
    data = truth.data
    data.location = Pose(state.x, state.y, state.theta)  # type: ignore[attr-defined]
    data.tv, data.rv, data.acceleration = state.tv, state.rv, state.acceleration  # type: ignore[attr-defined]
    truth.set_auto_timestamp(False)
    data.timestamp = Time(stamp)
    truth.publish_data()
    standard.publish(state.x, state.y, state.theta, state.tv, state.rv, stamp)  # type: ignore[attr-defined]


if __name__ == '__main__':
    sys.exit(main())
