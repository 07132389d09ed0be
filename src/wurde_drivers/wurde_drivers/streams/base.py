"""The streams of a robot base, shared by every base module (the rFLEX driver, the dummy base, ros_inputs).

A base module named ``N`` supplies, as WURDE's RFlexServer (guide 7.6) and Pluto's baseserver
(Pluto 4: cmdFlags 0 only), ``NDrive`` (SynchroDrive for a synchro drive, RobotDrive for a skid
steer), ``NCommand`` (ActuatorState), ``NMotion`` (Egomotion), ``NSonar``, ``NBumpers`` and
``NPower``, and the standard ROS topics beside them (:mod:`wurde_drivers.ros_std`,
:mod:`wurde_drivers.ros_std_base`): the tables of docs/simulator.md ("The simulated robot and the drivers").
Whatever backend moves the robot, consumers see the same streams, so no module can tell a dummy
from the real base.

The guide's examples disagree on which drive interface a base supplies, so every base supplies
its own kind on ``NDrive`` and the other kind as the typed view ``NDrive/<Interface>``
(:func:`wurde_core.naming.typed_view`); both drive one set-point (docs/wurde-drivers.md).

Before changing it: the base must fail safe.  Commands are velocity set-points with a watchdog (no
command for ``command_timeout`` seconds stops the base); only a Drive request that sets ``brake``
false releases the brake, never a Twist on ``cmd_vel`` or a Pluto command; a command with a NaN or
infinite value is refused whole and counted (``refused_commands``).

Odometry calibration (Pluto 6.1, 7.1): ``NCommand`` with cmdFlags 99 scales every later odometry
increment on ``NMotion`` and ``/N/odom`` (:mod:`.calibration`).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Iterable, Sequence

from wurde_core import CommsManager, Logger, Pose, Pose3D, Time
from wurde_core.naming import typed_view
from wurde_core.interfaces import (ActuatorState, Bumper, Egomotion, Power, RangeFinder, RobotDrive,
                                   SynchroDrive)

from ..mounting import Mounting
from ..ros_std import OdometryPublisher, TwistInbox
from ..ros_std_base import BatteryPublisher, BumperPublisher, SonarPublisher
from ..ros_std_covariance import OdometryCovariance
from ..ros_std_frames import StaticFrames, member_frame
from .calibration import CALIBRATE, OdometryCalibration

__all__ = ['BaseLimits', 'BaseStreams', 'VelocityCommand']


@dataclasses.dataclass(frozen=True)
class BaseLimits:
    """What the hardware allows (the drive's info reports these as the limits)."""

    max_tv: float
    max_rv: float
    tv_accel: float
    rv_accel: float
    wheel_base: float = 0.5


@dataclasses.dataclass(frozen=True)
class VelocityCommand:
    tv: float
    rv: float
    tv_accel: float
    rv_accel: float
    brake: bool = False


def _set(request: object) -> set[str]:
    return set(request.ros_message().set_fields)  # type: ignore[attr-defined]


class BaseStreams:
    """Suppliers of one base; call :meth:`register` once, then :meth:`take_command` every loop."""

    def __init__(self, name: str, *, synchro: bool, limits: BaseLimits, command_timeout: float,
                 logger: Logger | None = None, brake_release: bool = True,
                 odometry: OdometryCovariance | None = None) -> None:
        """:param brake_release: whether a Drive request may release the brake at all (the
            rFLEX config's ``brake-reset``); when not, such a request is refused whole.
        :param odometry: the odometry's error model for ``/N/odom``'s covariance (the module
            names the figures' source); None: no noise, the least variances only."""
        self.name = name
        self.brake_release = brake_release
        self.synchro = synchro
        self.limits = limits
        self.command_timeout = command_timeout
        self.logger = logger
        native, other = (SynchroDrive, RobotDrive) if synchro else (RobotDrive, SynchroDrive)
        self.drive = native(f'{name}Drive')
        #: The other drive interface, on the typed view of the same stream.
        self.drive_view = other(typed_view(f'{name}Drive', other.interface_name))
        self.command = ActuatorState(f'{name}Command')
        self.motion = Egomotion(f'{name}Motion')
        #: Stream names of the sonar ring and the bumpers (their frames follow them).
        self.sonar_stream, self.bumper_stream = f'{name}Sonar', f'{name}Bumpers'
        self.sonar = RangeFinder(self.sonar_stream)
        self.bumpers = Bumper(self.bumper_stream)
        self.power = Power(f'{name}Power')
        self.current = VelocityCommand(0.0, 0.0, limits.tv_accel, limits.rv_accel)
        self.tv_limit = limits.max_tv
        self.rv_limit = limits.max_rv
        self.last_command = -math.inf
        self.timeouts = 0
        self.refused_commands = 0
        self.odometry = odometry or OdometryCovariance(trans=0.0, rot=0.0, drift=0.0)
        self.calibration = OdometryCalibration()
        self._odom: OdometryPublisher | None = None
        self._twist: TwistInbox | None = None
        self._sonar_std: SonarPublisher | None = None
        self._bumper_std: BumperPublisher | None = None
        self._battery_std: BatteryPublisher | None = None
        self._frames: StaticFrames | None = None

    @property
    def objects(self) -> list[object]:
        return [self.drive, self.drive_view, self.command, self.motion, self.sonar, self.bumpers,
                self.power]

    def register(self, manager: CommsManager) -> None:
        for obj in self.objects:
            manager.register_supplier(obj)  # type: ignore[arg-type]
        node = manager.node
        self._odom = OdometryPublisher(node, self.name, covariance=self.odometry)
        self._twist = TwistInbox(node, self.name)
        self._sonar_std = SonarPublisher(node, self.name, self.sonar_stream)
        self._bumper_std = BumperPublisher(node, self.name, self.bumper_stream)
        self._battery_std = BatteryPublisher(node, self.name)
        self._frames = StaticFrames(node)

    # -- info ---------------------------------------------------------------------------------
    def publish_drive_info(self) -> None:
        """Publish the set-point on both drive interfaces."""
        for obj, synchro in ((self.drive, self.synchro), (self.drive_view, not self.synchro)):
            self._fill_drive_info(obj.info, synchro)
            obj.publish_info()

    def _fill_drive_info(self, info: object, synchro: bool) -> None:
        c = self.current
        info.brake.set_value(c.brake)  # type: ignore[attr-defined]
        if synchro:
            info.trans.set_value(c.tv)  # type: ignore[attr-defined]
            info.angular.set_value(c.rv)  # type: ignore[attr-defined]
            info.trans_limit.set_value(self.tv_limit)  # type: ignore[attr-defined]
            info.angular_limit.set_value(self.rv_limit)  # type: ignore[attr-defined]
            info.trans_accel.set_value(c.tv_accel)  # type: ignore[attr-defined]
            info.angular_accel.set_value(c.rv_accel)  # type: ignore[attr-defined]
            info.trans_decel.set_value(c.tv_accel)  # type: ignore[attr-defined]
            info.angular_decel.set_value(c.rv_accel)  # type: ignore[attr-defined]
            return
        info.mode.set_value(0)  # type: ignore[attr-defined]
        info.trans_velocity.set_value(c.tv)  # type: ignore[attr-defined]
        info.rot_velocity.set_value(c.rv)  # type: ignore[attr-defined]
        half = c.rv * self.limits.wheel_base / 2
        info.left_velocity.set_value(c.tv - half)  # type: ignore[attr-defined]
        info.right_velocity.set_value(c.tv + half)  # type: ignore[attr-defined]
        info.trans_limit.set_value(self.tv_limit)  # type: ignore[attr-defined]
        info.rot_limit.set_value(self.rv_limit)  # type: ignore[attr-defined]
        info.trans_accel.set_value(c.tv_accel)  # type: ignore[attr-defined]
        info.rot_accel.set_value(c.rv_accel)  # type: ignore[attr-defined]
        info.wheel_base.set_value(self.limits.wheel_base)  # type: ignore[attr-defined]

    def publish_sonar_info(self, *, count: int, max_range: float, half_angle: float, radius: float,
                           z: float) -> None:
        info = self.sonar.info
        info.max_range.set_value(max_range)
        info.uniform.set_value(True)
        info.half_angle.set_value(half_angle)
        info.x_offset.set_value(radius)
        info.y_offset.set_value(0.0)
        info.z_offset.set_value(z)
        info.theta_offset.set_value(0.0)
        info.theta_separation.set_value(2 * math.pi / count)
        info.sensor_positions.set_value([Pose3D(radius * math.cos(a), radius * math.sin(a), z, a, 0.0, 0.0)
                                         for a in (2 * math.pi * i / count for i in range(count))])
        self.announce_sonar()

    def _publish_frames(self, stream: str, positions: Sequence[Pose3D]) -> None:
        if self._frames is not None:
            self._frames.set((member_frame(stream, i), Mounting(p.x(), p.y(), p.z(), p.theta()))
                             for i, p in enumerate(positions))

    def announce_sonar(self) -> None:
        """Publish the sonar info as filled in, and its standard mirrors: a Range per sonar on
        ``/N/sonar`` and each sonar's frame at its ``sensor_positions`` on ``/tf_static``."""
        self.sonar.publish_info()
        info = self.sonar.info
        positions = list(info.sensor_positions.get_value())
        if self._sonar_std is not None:
            self._sonar_std.configure(count=len(positions), half_angle=info.half_angle.get_value(),
                                      max_range=info.max_range.get_value())
        self._publish_frames(self.sonar_stream, positions)

    def announce_bumpers(self) -> None:
        """Publish the bumper info as filled in, its Range mirror and its frames (as the sonar's)."""
        self.bumpers.publish_info()
        positions = list(self.bumpers.info.sensor_positions.get_value())
        if self._bumper_std is not None:
            self._bumper_std.configure(len(positions))
        self._publish_frames(self.bumper_stream, positions)

    def publish_bumper_info(self, radius: float, z: float = 0.2) -> None:
        info = self.bumpers.info
        info.uniform.set_value(False)
        info.sensor_positions.set_value([Pose3D(radius, 0.0, z, 0.0, 0.0, 0.0),
                                         Pose3D(-radius, 0.0, z, math.pi, 0.0, 0.0)])
        self.announce_bumpers()

    def publish_power_info(self, nominal: float, low: float, critical: float, capacity: float) -> None:
        info = self.power.info
        info.nominal_voltage.set_value(nominal)
        info.low_voltage.set_value(low)
        info.critical_voltage.set_value(critical)
        info.capacity.set_value(capacity)
        self.power.publish_info()
        if self._battery_std is not None:
            self._battery_std.configure(nominal_voltage=nominal, capacity_j=capacity)

    def publish_all_info(self) -> None:
        self.publish_drive_info()
        self.motion.info.origin.set_value(Pose(0.0, 0.0, 0.0))
        self.motion.publish_info()
        self._publish_command_state()

    # -- commands -----------------------------------------------------------------------------
    def take_command(self, now: float) -> VelocityCommand | None:
        """The new velocity command if one arrived, a stop if the last one is too old, else None.

        ``now`` is the base's clock in seconds (simulated time for the dummy).
        """
        changed = False
        for obj, synchro in ((self.drive, self.synchro), (self.drive_view, not self.synchro)):
            while obj.get_next_request():
                changed |= self._drive_request(obj, synchro)
        while self.command.get_next_request():
            changed |= self._pluto_request()
        twist = self._twist.take() if self._twist is not None else None
        if twist is not None:
            changed |= self._velocity(twist.linear.x, twist.angular.z, 'cmd_vel Twist')
        if changed:
            self.last_command = now
            self.publish_drive_info()
            self._publish_command_state()
            return self.current
        moving = self.current.tv != 0.0 or self.current.rv != 0.0
        if moving and now - self.last_command > self.command_timeout:
            self.timeouts += 1
            if self.logger is not None:
                self.logger.warn(f'{self.name}: no command for {self.command_timeout:.2f} s: stopping')
            self.current = dataclasses.replace(self.current, tv=0.0, rv=0.0)
            self.publish_drive_info()
            self._publish_command_state()
            return self.current
        return None

    def stop(self) -> VelocityCommand:
        """Stop now (the module went Idle, a bumper tripped): zero velocities, brake as it was."""
        self.current = dataclasses.replace(self.current, tv=0.0, rv=0.0)
        return self.current

    def _refuse(self, what: str, why: str) -> bool:
        self.refused_commands += 1
        if self.logger is not None:
            self.logger.warn(f'{self.name}: refused {what}: {why}')
        return False

    def _clamp(self, tv: float, rv: float) -> tuple[float, float]:
        return (max(-self.tv_limit, min(self.tv_limit, tv)), max(-self.rv_limit, min(self.rv_limit, rv)))

    def _velocity(self, tv: float, rv: float, what: str) -> bool:
        """A velocity command that is not a Drive request: never touches the brake."""
        if not (math.isfinite(tv) and math.isfinite(rv)):
            return self._refuse(what, f'not finite (tv={tv}, rv={rv})')
        if self.current.brake:
            return self._refuse(what, 'the brake is set; release it with a Drive request '
                                      '(brake false)')
        tv, rv = self._clamp(tv, rv)
        self.current = dataclasses.replace(self.current, tv=tv, rv=rv)
        return True

    def _drive_request(self, obj: object, synchro: bool) -> bool:
        req, fields = obj.requests, _set(obj.requests)  # type: ignore[attr-defined]
        values = {f: getattr(req, f).get_value() for f in fields if f != 'brake'}
        bad = {f: v for f, v in values.items() if isinstance(v, float) and not math.isfinite(v)}
        if bad:
            return self._refuse(f'{obj.interface_name} request', f'not finite: {bad}')  # type: ignore[attr-defined]
        c = self.current
        if 'brake' in fields and c.brake and not req.brake.get_value() and not self.brake_release:
            return self._refuse(f'{obj.interface_name} request', 'this base may not release its '  # type: ignore[attr-defined]
                                'brake (brake-reset="false")')
        tv, rv, tv_acc, rv_acc, brake = c.tv, c.rv, c.tv_accel, c.rv_accel, c.brake
        if synchro:
            names = {'trans': 'trans', 'angular': 'angular', 'tl': 'trans_limit', 'rl': 'angular_limit',
                     'ta': 'trans_accel', 'ra': 'angular_accel'}
        else:
            names = {'trans': 'trans_velocity', 'angular': 'rot_velocity', 'tl': 'trans_limit',
                     'rl': 'rot_limit', 'ta': 'trans_accel', 'ra': 'rot_accel'}
        if names['tl'] in fields:
            self.tv_limit = min(abs(values[names['tl']]), self.limits.max_tv)
        if names['rl'] in fields:
            self.rv_limit = min(abs(values[names['rl']]), self.limits.max_rv)
        if names['ta'] in fields and values[names['ta']] > 0:
            tv_acc = min(values[names['ta']], self.limits.tv_accel)
        if names['ra'] in fields and values[names['ra']] > 0:
            rv_acc = min(values[names['ra']], self.limits.rv_accel)
        if names['trans'] in fields:
            tv = values[names['trans']]
        if names['angular'] in fields:
            rv = values[names['angular']]
        if not synchro and 'mode' in fields and values['mode'] == 1:
            left, right = values.get('left_velocity', 0.0), values.get('right_velocity', 0.0)
            tv, rv = (left + right) / 2, (right - left) / self.limits.wheel_base
        if 'brake' in fields:
            brake = bool(req.brake.get_value())
        if brake:
            tv = rv = 0.0
        tv, rv = self._clamp(tv, rv)
        self.current = VelocityCommand(tv, rv, tv_acc, rv_acc, brake)
        return True

    def _pluto_request(self) -> bool:
        """Pluto's baseserver command (4): only cmdFlags 0, velocity[0..1] = (linear, angular)."""
        req = self.command.requests
        flags = req.cmd_flags.get_value()
        velocity = list(req.velocity.get_value())
        if flags == CALIBRATE:
            return self._calibrate([float(v) for v in req.force.get_value()])
        if flags != 0 or len(velocity) < 2:
            return self._refuse(f'{self.name}Command cmdFlags={flags} velocity={velocity}',
                                'the base takes cmdFlags 0 and velocity[0..1] only')
        return self._velocity(float(velocity[0]), float(velocity[1]), f'{self.name}Command')

    def _calibrate(self, scales: list[float]) -> bool:
        """cmdFlags 99: set the odometry calibration (force[0..1]); shown by the command data."""
        what = f'{self.name}Command calibration force={scales}'
        if len(scales) < 2:
            return self._refuse(what, 'force[0..1] must be the distance and rotation scales')
        problem = self.calibration.problem(scales[0], scales[1])
        if problem:
            return self._refuse(what, problem)
        self.calibration.set(scales[0], scales[1])
        if self.logger is not None:
            self.logger.notice(f'{self.name}: odometry calibration distance x{scales[0]:.5f} '
                               f'rotation x{scales[1]:.5f}')
        return True

    def _publish_command_state(self) -> None:
        data = self.command.data
        data.cmd_flags = 0
        data.velocity = [self.current.tv, self.current.rv]
        data.position = []
        data.force = [self.calibration.distance, self.calibration.rotation]
        data.acceleration = [self.current.tv_accel, self.current.rv_accel]
        self.command.publish_data()

    # -- data ---------------------------------------------------------------------------------
    def _stamp(self, obj: object, stamp: float | None) -> None:
        """Stamp with ``stamp``, or with the time of publishing when there is none (never the
        stamp an earlier event was given)."""
        obj.set_auto_timestamp(stamp is None)  # type: ignore[attr-defined]
        if stamp is not None:
            obj.data.timestamp = Time(stamp)  # type: ignore[attr-defined]

    def publish_motion(self, x: float, y: float, theta: float, tv: float, rv: float,
                       acceleration: float, stamp: float | None = None) -> None:
        """Publish the odometry (the raw pose and velocities; calibrated here)."""
        x, y, theta, tv, rv = self.calibration.apply(x, y, theta, tv, rv)
        data = self.motion.data
        data.location = Pose(x, y, theta)
        data.tv, data.rv, data.acceleration = tv, rv, acceleration
        self._stamp(self.motion, stamp)
        self.motion.publish_data()
        if self._odom is not None:
            self._odom.publish(x, y, theta, tv, rv, self._std_stamp(stamp))

    def publish_sonar(self, ranges: Iterable[float], stamp: float | None = None) -> None:
        self.sonar.data.ranges = [float(r) for r in ranges]
        self._stamp(self.sonar, stamp)
        self.sonar.publish_data()
        if self._sonar_std is not None:
            self._sonar_std.publish(self.sonar.data.ranges, self._std_stamp(stamp))

    @staticmethod
    def _std_stamp(stamp: float | None) -> float:
        return stamp if stamp is not None else time.time()

    def publish_bumpers(self, pressed: Sequence[bool], stamp: float | None = None) -> None:
        self.bumpers.data.bumpers = [bool(p) for p in pressed]
        self.bumpers.data.bumped = any(pressed)
        self._stamp(self.bumpers, stamp)
        self.bumpers.publish_data()
        if self._bumper_std is not None:
            self._bumper_std.publish(pressed, self._std_stamp(stamp))

    def publish_power(self, *, voltage: float, current: float, power: float, charge: float, energy: float,
                      low: float, critical: float, stamp: float | None = None) -> None:
        d = self.power.data
        d.voltage, d.current, d.power, d.charge, d.energy = voltage, current, power, charge, energy
        d.charging = False
        d.low, d.critical = voltage < low, voltage < critical
        self._stamp(self.power, stamp)
        self.power.publish_data()
        if self._battery_std is not None:
            self._battery_std.publish(voltage=voltage, current=current, charge=charge, charging=False,
                                      stamp=self._std_stamp(stamp))
