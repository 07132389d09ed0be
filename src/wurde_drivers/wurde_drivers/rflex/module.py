"""rflex_server: WURDE's RFlexServer (guide 7.6), an rFLEX base (B21r or ATRV-Jr) as a module.

It reads its ``<device>`` (chosen by the module name, ``-n``, default PlutoBase) from
``rflex-config.xml`` (:mod:`wurde_drivers.rflex.config`), drives the base through
:class:`~wurde_drivers.rflex.device.RFlexDriver` and supplies exactly the streams of the dummy
base (:class:`~wurde_drivers.streams.base.BaseStreams`).

Commands: whatever :meth:`BaseStreams.take_command` returns goes to the base, the watchdog's stop
included; the stream frontend owns the watchdog, so the driver's own is switched off.  Releasing
the brake is sent only when the config says ``brake-reset="true"``; otherwise it is refused and
logged, and the drive's info follows the brake the base reports.

Data go out at the base's report rate; nothing is published while the base is silent (never stale
data), and a port that cannot be opened is tried again from inside the loop (the module never
exits for a missing device).  docs/wurde-drivers.md ("rflex.module") says what is published when.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

from wurde_core import CommsManager, Logger, Pose3D, RunState

from ..errors import DeviceError, DeviceTimeout
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.retry import RetryGate
from ..ports.serial_link import SerialLink
from ..ros_std_covariance import OdometryCovariance
from ..streams.base import BaseLimits, BaseStreams, VelocityCommand
from . import codec
from .config import RFlexDevice, load_rflex_config
from .device import BAUDRATE, RFlexDriver
from .robots import BODY_M, ROBOTS, DriveKind, RobotParams

__all__ = ['RFlexModule', 'RFlexRunner', 'limits_for', 'main']

#: Loop sleep and the longest poll (the base reports every 100 ms).
SLEEP_S = 0.01
#: Longest the loop blocks in one connection attempt (well under the 1 s heartbeat TTL).
CONNECT_TIMEOUT_S = 0.5
#: Seconds between two attempts to open the port.
RETRY_S = 1.0
#: A base that sent nothing for this long (five report periods) is silent.
SILENT_AFTER_S = 0.5

#: Speed limits (m/s, rad/s) and track width (m) per robot type. rflex-config.xml names none;
#: these are estimates of what the robots can do safely indoors, not manufacturer figures.
SPEED_LIMITS = {name: (1.0, math.pi / 2) for name in ROBOTS}
WHEEL_BASE_M = {name: track for name, (_, _, track) in BODY_M.items()}
#: Polaroid 6500 sonars: reliable to about 10 m, a beam of about +-12.5 degrees.
SONAR_MAX_RANGE_M = 10.0
SONAR_HALF_ANGLE = math.radians(12.5)
#: Bumper panels: (radius m, height m) of each ring (B21r; approximate).
BUMPER_RINGS = {'body': (0.25, 0.6), 'base': (0.26, 0.15)}
#: Battery (both robots run on 24 V lead-acid packs); the dummy battery's thresholds.
NOMINAL_V, LOW_V, CRITICAL_V = 24.0, 22.0, 21.0
CAPACITY_J = 24.0 * 3600 * 40
#: Odometry error for ``/N/odom``'s covariance (trans per sqrt(m), rot per sqrt(rad), drift rad/m).
#: Neither the rFLEX nor the robots document an odometry accuracy (the encoders' resolution,
#: robots.py, is far finer than wheel slip), so these are the simulated Pluto's figures
#: (config/pluto/sim-config.xml, <odometry-noise>), which stand for this base's error.
ODOMETRY_NOISE = {'trans': 0.05, 'rot': 0.05, 'drift': 0.02}


def limits_for(robot: RobotParams) -> BaseLimits:
    """What the drive's info reports as the hardware limits of ``robot``.

    :param robot: the configured robot type (speed limits, accelerations, track width).
    """
    max_tv, max_rv = SPEED_LIMITS[robot.name]
    return BaseLimits(max_tv, max_rv, robot.trans_accel, robot.rot_accel,
                      wheel_base=WHEEL_BASE_M[robot.name])


def publish_sensor_info(streams: BaseStreams, robot: RobotParams) -> None:
    """Sonar, bumper and power info from the robot's parameters (explicit poses, not uniform).

    :param streams: the base's streams, registered.
    :param robot: gives the sonar poses and the bumper panels.
    """
    sonar = streams.sonar.info
    sonar.max_range.set_value(SONAR_MAX_RANGE_M)
    sonar.uniform.set_value(False)
    sonar.half_angle.set_value(SONAR_HALF_ANGLE)
    sonar.sensor_positions.set_value([Pose3D(s.x, s.y, s.z, s.yaw, 0.0, 0.0) for s in robot.sonars])
    streams.announce_sonar()
    positions = []
    for panel in robot.bumpers:
        radius, z = BUMPER_RINGS[panel.ring]
        positions.append(Pose3D(radius * math.cos(panel.yaw), radius * math.sin(panel.yaw), z,
                                panel.yaw, 0.0, 0.0))
    streams.bumpers.info.uniform.set_value(False)
    streams.bumpers.info.sensor_positions.set_value(positions)
    streams.announce_bumpers()
    streams.publish_power_info(NOMINAL_V, LOW_V, CRITICAL_V, CAPACITY_J)


class RFlexModule:
    """The module's work per loop turn: connect, commands, poll, publish, watch for silence."""

    def __init__(self, device: RFlexDevice, driver: RFlexDriver, streams: BaseStreams,
                 logger: Logger) -> None:
        """Nothing is connected yet: the first :meth:`step` tries.

        :param device: the configured device.
        :param driver: the device layer (constructed, not connected, its own watchdog off).
        :param streams: the base's streams (registered, info published).
        :param logger: where connection, brake and silence changes are logged (once each).
        """
        self.device = device
        self.driver = driver
        self.streams = streams
        self.logger = logger
        self.connected = False
        self.silent = False
        self._failures = 0
        self._retry = RetryGate(RETRY_S)
        self._brake = False            # the brake we asked for (BaseStreams' current.brake)
        self._resyncs = 0
        self._reported_brake: bool | None = None
        self._last_bumpers: list[bool] | None = None
        self._last_motion: tuple[float, float] | None = None   # (monotonic, tv)

    # -- connection ---------------------------------------------------------------------------
    def _try_connect(self) -> None:
        if not self._retry.due(time.monotonic()):
            return
        port = self.device.port
        try:
            self.driver.connect(CONNECT_TIMEOUT_S)
        except DeviceTimeout:
            # The port is open; the driver keeps sending the start-up sequence until it answers.
            self.connected = self.silent = True
            self.logger.warn(f'rFLEX base on {port} does not answer; publishing nothing until it '
                             'does')
        except DeviceError as error:
            self.driver.link.close()   # open afresh next time (the port may be replaced)
            if self._failures == 0:
                self.logger.warn(f'rFLEX base not ready: {error}; trying again every '
                                 f'{RETRY_S:g} s')
            self._failures += 1
            return
        else:
            self.connected = True
            self.logger.notice(f'{self.device.robot.name} base on {port} answers (brake-reset '
                               f'{"true" if self.device.brake_reset else "false"})')
        self._resyncs = self.driver.resyncs
        if self._brake:
            self.driver.brake(True)    # the start-up sequence may have released it

    # -- commands -----------------------------------------------------------------------------
    def handle_commands(self) -> None:
        """Send the command the streams hold, if a new one came or the watchdog stopped it."""
        command = self.streams.take_command(time.monotonic())
        if command is not None:
            self._send(command)

    def stop(self) -> None:
        """Stop the base now (the module goes Idle: nothing may drive it unattended)."""
        if self.connected:
            try:
                self._send(self.streams.stop())
            except DeviceError as error:
                self.logger.warn(f'{self.streams.name}: could not stop the base: {error}')

    def _send(self, command: VelocityCommand) -> None:
        if command.brake != self._brake:
            if command.brake:
                self.driver.brake(True)
            elif self.device.brake_reset:
                self.driver.brake(False)
            else:
                self.logger.warn(f'{self.streams.name}: brake release refused: the config does '
                                 'not allow it (brake-reset="false")')
                command = self._hold_brake()
            self._brake = command.brake
        try:
            self.driver.set_velocity(command.tv, command.rv, command.tv_accel, command.rv_accel)
        except ValueError as error:
            self.logger.warn(f'{self.streams.name}: command refused: {error}')

    def _hold_brake(self) -> VelocityCommand:
        """The streams' command with the brake set and no motion; its info published."""
        streams = self.streams
        streams.current = dataclasses.replace(streams.current, brake=True, tv=0.0, rv=0.0)
        streams.publish_drive_info()
        return streams.current

    def _follow_brake(self, brake: bool) -> None:
        """The base reported its brake: log a change; follow it when we may not release it."""
        if brake == self._reported_brake:
            return
        self._reported_brake = brake
        if self.device.brake_reset:
            return
        if brake:
            self.logger.warn(f'{self.streams.name}: the brake is set and brake-reset is false: '
                             'the base will not move until it is released by hand')
            self._hold_brake()
        else:
            self.logger.notice(f'{self.streams.name}: the brake was released')
            self.streams.current = dataclasses.replace(self.streams.current, brake=False)
            self.streams.publish_drive_info()
        self._brake = brake

    # -- data ---------------------------------------------------------------------------------
    def step(self, timeout: float) -> None:
        """One turn: commands, then connect if needed, else a poll of up to ``timeout`` s.

        :param timeout: the longest poll in seconds.
        """
        self.handle_commands()
        if not self.connected:
            self._try_connect()
            return
        reports = self.driver.poll(timeout)
        if self.driver.resyncs != self._resyncs:
            self._resyncs = self.driver.resyncs
            if self._brake:
                self.driver.brake(True)   # the resent start-up sequence released it
        silent_for = self.driver.silent_for()
        if silent_for > SILENT_AFTER_S:
            if not self.silent:
                self.silent = True
                self.logger.warn(f'rFLEX base on {self.device.port} is silent (nothing for '
                                 f'{silent_for:.1f} s); publishing nothing until it is back'
                                 f'{self.driver.link.fault_note()}')
            return
        if self.silent:
            self.silent = False
            self._last_motion = self._last_bumpers = None
            self.logger.notice(f'rFLEX base on {self.device.port} is back')
        self.publish(reports)

    def publish(self, reports: list[codec.Report | codec.Packet]) -> None:
        """Publish what ``reports`` (just decoded into the driver's state) brought.

        :param reports: what :meth:`RFlexDriver.poll` returned this turn.
        """
        state, robot, streams = self.driver.state, self.driver.robot, self.streams
        now, stamp = time.monotonic(), time.time()
        odometry = any(isinstance(r, codec.MotorReport) and r.axis == 1 for r in reports)
        if odometry and state.odometry_ready:
            last, self._last_motion = self._last_motion, (now, state.tv)
            accel = (state.tv - last[1]) / (now - last[0]) if last and now > last[0] else 0.0
            streams.publish_motion(state.x, state.y, state.theta, state.tv, state.rv, accel, stamp)
        bumpers = [bool(state.bumpers.get(panel.address, 0)) for panel in robot.bumpers]
        if odometry or (bumpers != self._last_bumpers and any(
                isinstance(r, codec.DioReport) for r in reports)):
            streams.publish_bumpers(bumpers, stamp)
            self._last_bumpers = bumpers
        if any(isinstance(r, codec.SonarReport) for r in reports):
            streams.publish_sonar([min(r, SONAR_MAX_RANGE_M) for r in state.sonar], stamp)
        if any(isinstance(r, codec.SystemStatus) for r in reports):
            if state.brake is not None:
                self._follow_brake(state.brake)
            if state.voltage > 0:
                charge = min(1.0, max(0.0, (state.voltage - CRITICAL_V)
                                      / (1.1 * NOMINAL_V - CRITICAL_V)))
                streams.publish_power(voltage=state.voltage, current=math.nan, power=math.nan,
                                      charge=charge, energy=charge * CAPACITY_J, low=LOW_V,
                                      critical=CRITICAL_V, stamp=stamp)

    def close(self) -> None:
        """Stop the base, switch its reports off and close the port (idempotent)."""
        self.driver.close()
        self.connected = False


RFlexRunner = RFlexModule  # old name (docs/naming.md)


def main(argv: list[str] | None = None) -> int:
    """The ``rflex_server`` program (also ``rFlexServer``, ``rFlexServerII``): one ``<device>`` of
    rflex-config.xml as a base module.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoBase')
    device = configured_device(manager, argv, 'rflex-config.xml', load_rflex_config)
    robot = device.robot
    logger = Logger(manager.name)
    streams = BaseStreams(manager.name, synchro=robot.drive is DriveKind.SYNCHRO,
                          limits=limits_for(robot), command_timeout=device.command_timeout,
                          logger=logger, brake_release=device.brake_reset,
                          odometry=OdometryCovariance(**ODOMETRY_NOISE))
    driver = RFlexDriver(SerialLink(device.port, BAUDRATE), robot, brake_reset=device.brake_reset,
                         command_timeout=None)
    runner = RFlexModule(device, driver, streams, logger)
    streams.register(manager)
    manager.register_supplier(logger)
    set_loop(manager, SLEEP_S)
    manager.on_state(RunState.IDLE, runner.stop)
    streams.publish_all_info()
    publish_sensor_info(streams, robot)
    return run_loop(manager, lambda: runner.step(SLEEP_S), runner.close)


if __name__ == '__main__':
    sys.exit(main())
