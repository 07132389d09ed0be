"""The rFLEX base driver (B21r, ATRV-Jr) over a :class:`SerialLink` at 115200 8N1; no ROS.

Life cycle (docs/style.md): construct (no I/O) -> :meth:`RFlexDriver.connect` (may raise) -> call
:meth:`~RFlexDriver.poll` in the module's loop (never blocks longer than asked, never raises on bad
bytes) -> :meth:`~RFlexDriver.close` (idempotent). One thread uses a driver.

``connect`` sends what Player, CARMEN and DLu send at start-up (docs/protocols.md 3): SET_DEFAULTS,
odometry reports every 100000 us for axes 0 and 1 (mask 3), SONAR_RUN on, DIO reports on, and
BRAKE_RELEASE only if the configuration allows it (WURDE 7.6 "whether the module should be allowed
to reset the brake"), then a SYS_STATUS poll. ``poll`` re-polls SYS_STATUS every
``status_period_s`` (voltage, brake), stops the base when no velocity command came for
``command_timeout`` seconds, and re-sends the start-up sequence when the link was reopened after
the device vanished, or every ``resend_s`` while the base is silent or sends no odometry (a
power-cycled base has forgotten every request, but may still answer the SYS_STATUS polls).

Odometry: the pose integrates the deltas of the axis-0 distance and axis-1 bearing counters
(signed 32-bit, wrap handled), pairing each distance delta with the bearing delta that follows it
and moving along the exact arc of constant curvature. A jump beyond ``max_step`` (a counter reset)
re-baselines instead. Units: metres, radians, seconds; sonar ranges in metres, ``inf`` = no echo;
voltage in volts (``raw / 100 + 1.2``, see :mod:`wurde_drivers.rflex.robots`).
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

from ..errors import CodecError, DeviceError, DeviceTimeout
from ..ports.serial_link import LinkStats, SerialLink
from . import codec
from .config import RFlexDevice
from .robots import (B21R, HEADING_HOME_ADDRESS, RobotParams, sonar_range_m,
                            voltage_v)

__all__ = ['BAUDRATE', 'RFlexDriver', 'RFlexState']

BAUDRATE = 115200


@dataclasses.dataclass
class RFlexState:
    """What the driver knows about the base; updated by :meth:`RFlexDriver.poll`."""

    x: float = 0.0                 # odometry pose (m, m, rad in (-pi, pi])
    y: float = 0.0
    theta: float = 0.0
    distance: float = 0.0          # signed path length integrated (m)
    tv: float = 0.0                # measured translational velocity (m/s)
    rv: float = 0.0                # measured rotational velocity (rad/s)
    trans_accel: float = 0.0       # acceleration the base reports (m/s^2, rad/s^2)
    rot_accel: float = 0.0
    sonar: list[float] = dataclasses.field(default_factory=list)   # m per robot sonar; inf
    bumpers: dict[int, int] = dataclasses.field(default_factory=dict)  # panel address -> bits
    dio: dict[int, int] = dataclasses.field(default_factory=dict)      # every DIO address seen
    voltage: float = math.nan
    brake: bool | None = None      # True = brake set; None until the first SYS_STATUS
    joystick: tuple[int, int, int] | None = None
    home_bearing: int | None = None    # bearing counter at the last heading-home DIO event
    odometry_ready: bool = False   # both counters seen since the last (re)connect
    last_report: float | None = None   # time.monotonic() of the last valid packet

    @property
    def bumped(self) -> bool:
        """Is any bumper panel pressed."""
        return any(self.bumpers.values())


class RFlexDriver:
    """An rFLEX base on a serial link; see the module docstring for the life cycle."""

    def __init__(self, link: SerialLink, robot: RobotParams = B21R, *, brake_reset: bool = False,
                 command_timeout: float | None = 1.0, odometry_period_us: int = 100000,
                 dio_period: int = 100000, sonar: bool = True, status_period_s: float = 1.0,
                 silence_s: float = 1.0, resend_s: float = 1.0, max_step: float = 2.0) -> None:
        """Keep the settings; no I/O until :meth:`connect`.

        :param link: the port (115200 baud); :meth:`from_config` builds it from rflex-config.xml.
        :param robot: units, sonars and bumpers of the robot.
        :param brake_reset: may the driver release the brake (connect, :meth:`brake`).
        :param command_timeout: stop the base when no :meth:`set_velocity` came for this long
            (seconds; None never).
        :param odometry_period_us: the MOT_SYSTEM_REPORT period asked for at start-up (µs, axes 0
            and 1); 0 asks for no odometry.
        :param dio_period: the DIO_REPORTS_REQ period asked for at start-up; 0 turns DIO reports off.
        :param sonar: run the sonars (SONAR_RUN at start-up).
        :param status_period_s: seconds between two SYS_STATUS polls (voltage, brake).
        :param silence_s: the base counts as silent after this long without a valid packet; must
            exceed the report period.
        :param resend_s: seconds between two re-sends of the start-up sequence while the base is
            silent or sends no odometry.
        :param max_step: metres (distance) or radians (bearing) between two counter readings beyond
            which the counter is taken as reset and re-baselined, not integrated.
        """
        self.link = link
        self.robot = robot
        self.brake_reset = brake_reset
        self.command_timeout = command_timeout
        self.odometry_period_us = odometry_period_us
        self.dio_period = dio_period
        self.sonar = sonar
        self.status_period_s = status_period_s
        self.silence_s = silence_s
        self.resend_s = resend_s
        self.max_step = max_step
        self.state = RFlexState(sonar=[math.inf] * len(robot.sonars))
        #: Valid packets that were not a known report or carried a malformed one.
        self.bad_reports = 0
        #: Times the start-up sequence was sent again (reconnect or silence).
        self.resyncs = 0
        #: Counter jumps beyond ``max_step`` (re-baselined instead of integrated).
        self.odometry_resets = 0
        self._deframer = codec.Deframer()
        self._connected_at: float | None = None
        self._seen_reconnects = 0
        self._next_status = self._next_resend = 0.0
        self._silent = False
        self._last_odometry: float | None = None
        self._last_command = 0.0
        self._moving = False
        self._counters: list[int | None] = [None, None]
        self._pending_distance: float | None = None

    @classmethod
    def from_config(cls, device: RFlexDevice, **options: Any) -> 'RFlexDriver':
        """A driver for one ``<device>`` of rflex-config.xml (no I/O yet).

        :param device: gives the port, the robot type, ``brake-reset`` and ``command-timeout``.
        :param options: any other keyword of :meth:`__init__`.
        """
        return cls(SerialLink(device.port, BAUDRATE), device.robot,
                   brake_reset=device.brake_reset, command_timeout=device.command_timeout,
                   **options)

    @property
    def stats(self) -> LinkStats:
        """The link's counters (bytes, telegrams, bad CRC, skipped bytes, timeouts, reconnects)."""
        return self.link.stats

    # -- life cycle --------------------------------------------------------------------------
    def connect(self, timeout: float = 2.0) -> None:
        """Open the port, send the start-up sequence and wait up to ``timeout`` for an answer.

        :param timeout: seconds to wait for the first valid packet; 0 does not wait.
        :raises DeviceError: the port cannot be opened.
        :raises DeviceTimeout: nothing valid came back within ``timeout`` (> 0). The port stays
            open: :meth:`poll` keeps re-sending the start-up sequence until the base answers, so a
            module may carry on and report the base as silent, or :meth:`close`.
        """
        self.link.open()
        self.link.reset_input()
        self._deframer.reset()
        now = time.monotonic()
        self._connected_at = now
        self._last_odometry = None
        self._seen_reconnects = self.link.stats.reconnects
        self._resync(now, count=False)
        if timeout <= 0:
            return
        deadline = now + timeout
        while self.state.last_report is None or self.state.last_report < now:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise DeviceTimeout(f'{self.link.url}: the rFLEX base did not answer in '
                                    f'{timeout:g} s')
            self.poll(remaining)

    def close(self) -> None:
        """Stop the base, switch its reports off and close the port (idempotent)."""
        if self.link.is_open:
            self.stop()
            for packet in (codec.system_report_req(0, 0), codec.sonar_run(False),
                           codec.dio_reports_req(0)):
                self._write(packet)
        self.link.close()
        self._connected_at = None

    # -- commands ---------------------------------------------------------------------------
    def set_velocity(self, trans_mps: float, rot_radps: float, trans_accel: float | None = None,
                     rot_accel: float | None = None) -> bool:
        """Command both axes (SET_DIR for axis 0 and 1, magnitude plus direction bit).

        Velocities and accelerations are moved off 0x1B bytes (Player's workaround,
        :func:`esc_free_set_dir`).

        :param trans_mps: translational velocity, m/s (negative backwards).
        :param rot_radps: rotational velocity, rad/s, in the sense of the odometry's theta.
        :param trans_accel: m/s²; None: the robot's (0.7 m/s²).
        :param rot_accel: rad/s²; None: the robot's (Player's 100000 counts/s²).
        :returns: False if the device is not there or the driver is not connected (the command
            is lost).
        :raises ValueError: a value that is not finite, a negative acceleration, or out of range.
        """
        values = (trans_mps, rot_radps, trans_accel or 0.0, rot_accel or 0.0)
        if not all(math.isfinite(v) for v in values) or min(values[2:]) < 0:
            raise ValueError(f'bad rFLEX velocity command {values}')
        tv, rv = self.robot.counts_from_m(trans_mps), self.robot.counts_from_rad(rot_radps)
        ta = self.robot.counts_from_m(
            self.robot.trans_accel if trans_accel is None else trans_accel)
        ra = (self.robot.rot_accel_counts if rot_accel is None
              else self.robot.counts_from_rad(rot_accel))
        if max(abs(tv), abs(rv), ta, ra) >= 1 << 31:
            raise ValueError(f'rFLEX velocity command out of range {values}')
        try:
            packets = (codec.esc_free_set_dir(0, abs(tv), ta, self.robot.trans_torque,
                                              int(tv >= 0)),
                       codec.esc_free_set_dir(1, abs(rv), ra, self.robot.rot_torque,
                                              int(rv >= 0)))
        except CodecError as error:
            raise ValueError(str(error)) from error
        self._last_command = time.monotonic()
        self._moving = tv != 0 or rv != 0
        return all([self._write(packet) for packet in packets])

    def stop(self) -> bool:
        """Zero velocity on both axes (with the default decelerations)."""
        return self.set_velocity(0.0, 0.0)

    def brake(self, on: bool) -> bool:
        """Set or release the brake, then poll SYS_STATUS so :attr:`state` follows.

        :param on: True sets the brake, False releases it.
        :returns: False if either packet could not be written.
        :raises DeviceError: releasing when the configuration does not allow it (``brake_reset``).
        """
        if not on and not self.brake_reset:
            raise DeviceError('releasing the rFLEX brake is not allowed by the configuration '
                              '(brake-reset="false")')
        sent = self._write(codec.brake_set() if on else codec.brake_release())
        return self._write(codec.sys_status_poll()) and sent

    # -- input ------------------------------------------------------------------------------
    def poll(self, timeout: float) -> list[codec.Report | codec.Packet]:
        """Read for at most ``timeout`` s; return as soon as something was decoded.

        Updates :attr:`state` and returns the reports (packets of other kinds unchanged). Bad
        bytes are counted in :attr:`stats` and skipped; never raises on them.

        :param timeout: the longest wait in seconds.
        :raises DeviceError: the driver is not connected (before :meth:`connect`, after
            :meth:`close`).
        """
        if self._connected_at is None:
            raise DeviceError(f'{self.link.url}: the rFLEX driver is not connected')
        deadline = time.monotonic() + max(0.0, timeout)
        self._housekeeping(time.monotonic())
        found: list[codec.Report | codec.Packet] = []
        while True:
            remaining = deadline - time.monotonic()
            data = self.link.read(max(0.0, remaining))
            if data:
                found += self._ingest(data)
            elif not self.link.is_open and remaining > 0:
                time.sleep(min(remaining, 0.02))   # port gone: wait for the retry, within budget
            if found or time.monotonic() >= deadline:
                break
        self._housekeeping(time.monotonic())
        return found

    def silent_for(self) -> float:
        """Seconds since the last valid packet (since connect if none; inf before connect)."""
        last = self.state.last_report or self._connected_at
        return math.inf if last is None else time.monotonic() - last

    @property
    def silent(self) -> bool:
        return self.silent_for() > self.silence_s

    # -- internals --------------------------------------------------------------------------
    def _write(self, packet: codec.Packet) -> bool:
        """Send ``packet``; never reopens a port the driver has closed."""
        return self._connected_at is not None and self.link.write(codec.encode(packet))

    def _resync(self, now: float, *, count: bool = True) -> None:
        """(Re)send the start-up sequence and restart the odometry baselines."""
        sequence = [codec.set_defaults(), codec.system_report_req(self.odometry_period_us, 3)]
        if self.sonar:
            sequence.append(codec.sonar_run(True))
        sequence.append(codec.dio_reports_req(self.dio_period))
        if self.brake_reset:
            sequence.append(codec.brake_release())
        sequence.append(codec.sys_status_poll())
        for packet in sequence:
            self._write(packet)
        self._counters = [None, None]
        self._pending_distance = None
        self.state.odometry_ready = False
        self._next_status = now + self.status_period_s
        self._next_resend = now + self.resend_s
        self.resyncs += count

    def _housekeeping(self, now: float) -> None:
        if self._connected_at is None or not self.link.is_open:
            return
        if self.link.stats.reconnects != self._seen_reconnects:
            self._seen_reconnects = self.link.stats.reconnects
            self._deframer.reset()
            self._resync(now)
        elif (self.silent or self._odometry_stopped(now)) and now >= self._next_resend:
            if self.silent and not self._silent:
                self._silent = True
                self.link.stats.timeouts += 1
            self._resync(now)
        if now >= self._next_status:
            self._next_status = now + self.status_period_s
            self._write(codec.sys_status_poll())
        if (self._moving and self.command_timeout is not None
                and now - self._last_command > self.command_timeout):
            self.stop()

    def _odometry_stopped(self, now: float) -> bool:
        """Odometry was requested but no motor report came for ``silence_s``: a base that
        still answers polls has forgotten the request (it was power-cycled while unplugged)."""
        if not self.odometry_period_us:
            return False
        last = self._last_odometry or self._connected_at
        return last is not None and now - last > self.silence_s

    def _ingest(self, data: bytes) -> list[codec.Report | codec.Packet]:
        deframer, stats = self._deframer, self.link.stats
        bad_crc, skipped = deframer.bad_crc, deframer.bytes_skipped
        packets = deframer.feed(data)
        stats.telegrams += len(packets)
        stats.bad_crc += deframer.bad_crc - bad_crc
        stats.bytes_skipped += deframer.bytes_skipped - skipped
        found: list[codec.Report | codec.Packet] = []
        now = time.monotonic()
        for packet in packets:
            self.state.last_report = now
            self._silent = False
            try:
                report = codec.decode_report(packet)
            except CodecError:
                self.bad_reports += 1
                continue
            if isinstance(report, codec.Packet):
                self.bad_reports += 1
            else:
                if isinstance(report, codec.MotorReport):
                    self._last_odometry = now
                self._apply(report)
            found.append(report)
        return found

    def _apply(self, report: codec.Report) -> None:
        state, robot = self.state, self.robot
        if isinstance(report, codec.MotorReport):
            self._odometry(report)
        elif isinstance(report, codec.SystemStatus):
            state.voltage = voltage_v(report.voltage_raw, robot.voltage_offset)
            state.brake = report.brake
        elif isinstance(report, codec.SonarReport):
            for sonar_id, raw in report.readings:
                index = robot.sonar_index(sonar_id)
                if index is not None:
                    state.sonar[index] = sonar_range_m(raw)
        elif isinstance(report, codec.DioReport):
            state.dio[report.address] = report.value
            if robot.bumper(report.address) is not None:
                state.bumpers[report.address] = report.value
            elif report.address == HEADING_HOME_ADDRESS:
                state.home_bearing = self._counters[1]
        elif isinstance(report, codec.JoystickState):
            state.joystick = (report.x, report.y, report.buttons)

    def _odometry(self, report: codec.MotorReport) -> None:
        axis, state, robot = report.axis, self.state, self.robot
        if axis not in (0, 1):
            return
        if axis == 0:
            state.tv = robot.m_from_counts(report.velocity)
            state.trans_accel = robot.m_from_counts(report.acceleration)
        else:
            state.rv = robot.rad_from_counts(report.velocity)
            state.rot_accel = robot.rad_from_counts(report.acceleration)
        last, self._counters[axis] = self._counters[axis], report.position
        if last is None:
            state.odometry_ready = None not in self._counters
            return
        delta = ((report.position - last + (1 << 31)) % (1 << 32)) - (1 << 31)
        step = robot.m_from_counts(delta) if axis == 0 else robot.rad_from_counts(delta)
        if abs(step) > self.max_step:
            self.odometry_resets += 1
            return
        if axis == 0:
            if self._pending_distance is not None:
                self._integrate(self._pending_distance, 0.0)
            self._pending_distance = step
        else:
            self._integrate(self._pending_distance or 0.0, step)
            self._pending_distance = None

    def _integrate(self, distance: float, turn: float) -> None:
        """Move ``distance`` along an arc turning by ``turn`` (exact for constant curvature)."""
        state, half = self.state, turn / 2.0
        chord = distance * (math.sin(half) / half if abs(half) > 1e-9 else 1.0)
        heading = state.theta + half
        state.x += chord * math.cos(heading)
        state.y += chord * math.sin(heading)
        state.theta = math.remainder(state.theta + turn, math.tau)
        state.distance += distance
