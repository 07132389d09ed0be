"""An rFLEX base (B21r or ATRV-Jr) on a pseudo-terminal, speaking the real protocol at 115200 8N1.

What it does (docs/protocols.md 3):

- accepts every host command of the codec; SET_DIR sets an axis' signed velocity (counts/s) and
  acceleration (counts/s^2); the emulator ramps each axis towards it and integrates axis 0 into the
  distance counter and axis 1 into the bearing counter (signed 32-bit, wrapping);
- after MOT_SYSTEM_REPORT_REQ, sends one MOT_SYSTEM_REPORT per axis of the mask every period
  (period 0 stops them); answers SYS_STATUS with the voltage and the brake, JSTK with its state;
- the brake starts set (as on DLu's driver); while it is set the base does not move;
- sends a SONAR_REPORT for all sonars every ``sonar_period_s`` while SONAR_RUN is on (ranges from
  ``sonar_ranges()``, metres in the robot's sonar order; default: no echo), and a DIO_REPORT when a
  test presses a bumper (:meth:`set_bumper`) while DIO reports are on.

By default no 0x1B is put inside a packet (docs/protocols.md's recommendation): fields are moved to the
nearest ESC-free value (:func:`esc_free`: at most 128 counts away below 0x1B0000, i.e. 17 m of
distance) and report IDs whose CRC would be 0x1B are skipped. ``stuff_esc=True`` sends exact
values with each ESC as ``1B 00``.

Faults: :meth:`corrupt_next` (bad CRC), :attr:`garbage` (bytes before every packet), :attr:`silent`
(nothing sent, commands still obeyed), :meth:`unplug` / :meth:`replug` (optionally a power cycle
that forgets every request and zeroes the counters).
"""

from __future__ import annotations

import collections
import math
import struct
import threading
import time
from collections.abc import Callable, Sequence

from ..ports.pty import PtyEmulator
from . import codec
from .codec import Dio, Ir, Jstk, Mot, Packet, Port, Sonar, Sys
from .robots import B21R, RobotParams, sonar_range_raw, voltage_raw

__all__ = ['RFlexEmulator']


def _wrap32(value: float) -> int:
    return ((int(round(value)) + (1 << 31)) % (1 << 32)) - (1 << 31)


class RFlexEmulator(PtyEmulator):
    """An rFLEX base; :attr:`path` is what the driver opens."""

    def __init__(self, robot: RobotParams = B21R, *,
                 sonar_ranges: Callable[[], Sequence[float]] | None = None,
                 voltage: float = 26.0, brake: bool = True, stuff_esc: bool = False,
                 sonar_period_s: float = 0.1, tick_s: float = 0.005) -> None:
        """Open the pty and power up (counters zero, nothing requested); :meth:`start` runs it.

        :param robot: units, sonars and bumpers of the base.
        :param sonar_ranges: returns metres in the robot's sonar order for each SONAR_REPORT; None:
            no echo.
        :param voltage: volts the SYS_STATUS reply reports.
        :param brake: whether the brake is set at power-up (as on DLu's driver).
        :param stuff_esc: send exact values with each ESC as ``1B 00``; False moves fields off 0x1B.
        :param sonar_period_s: seconds between two SONAR_REPORTs while the sonars run.
        :param tick_s: seconds between two turns of the emulator's thread.
        """
        super().__init__(tick_s=tick_s)
        self.robot = robot
        self.sonar_ranges = sonar_ranges
        self.voltage = voltage
        self.stuff_esc = stuff_esc
        self.sonar_period_s = sonar_period_s
        #: Bytes written before every packet while not empty (garbage between packets).
        self.garbage = b''
        #: While set the base sends nothing but still obeys commands.
        self.silent = threading.Event()
        self.joystick = (0, 0, 0)
        self._lock = threading.Lock()
        self._deframer = codec.Deframer()
        self._received: list[Packet] = []
        self.bad_commands = 0
        self._corrupt = 0
        self._packet_id = 0
        self._t0 = time.monotonic()
        self.motor_report_times: collections.deque[float] = collections.deque(maxlen=2000)
        self._power_on(brake)

    def _power_on(self, brake: bool) -> None:
        """The state after power-up: nothing requested, counters zero."""
        self.brake = brake
        self._cmd_vel = [0, 0]
        self._cmd_acc = [0, 0]
        self._torque = [0, 0]
        self._vel = [0.0, 0.0]
        self._pos = [0.0, 0.0]
        self._report_period = 0.0
        self._report_mask = 0
        self._next_report = 0.0
        self.sonar_on = False
        self._next_sonar = 0.0
        self.dio_period = 0
        self._bumpers: dict[int, int] = {}
        self._dio_events: list[tuple[int, int]] = []
        self._last_tick: float | None = None

    # -- test-side API ----------------------------------------------------------------------
    def commands(self) -> list[Packet]:
        """Every valid packet the driver sent, in order."""
        with self._lock:
            return list(self._received)

    @property
    def report_period_s(self) -> float:
        return self._report_period

    def distance_m(self) -> float:
        """The exact distance travelled (axis 0) in metres."""
        with self._lock:
            return self._pos[0] / self.robot.units_per_m

    def bearing_rad(self) -> float:
        """The exact bearing turned (axis 1) in radians."""
        with self._lock:
            return self._pos[1] / self.robot.units_per_rad

    def velocities(self) -> tuple[float, float]:
        """The actual (m/s, rad/s) of the base."""
        with self._lock:
            return self._vel[0] / self.robot.units_per_m, self._vel[1] / self.robot.units_per_rad

    def set_counter(self, axis: int, counts: int) -> None:
        """Put a counter at ``counts`` (e.g. near the 32-bit wrap).

        :param axis: 0 the distance counter, 1 the bearing counter.
        :param counts: the new value, in the robot's units.
        """
        with self._lock:
            self._pos[axis] = float(counts)

    def set_bumper(self, address: int, value: int) -> None:
        """Press or release a bumper panel; reported while DIO reports are on.

        :param address: the panel's DIO address (B21r: 0x40-0x4D).
        :param value: the switches pressed (low 4 bits); 0 releases the panel.
        """
        with self._lock:
            self._bumpers[address] = value
            self._dio_events.append((address, value))

    def corrupt_next(self, count: int = 1) -> None:
        """Send the next ``count`` packets with a wrong CRC.

        :param count: how many; added to any still pending.
        """
        with self._lock:
            self._corrupt += count

    def unplug(self) -> None:
        """The base vanishes: nothing is read or written until :meth:`replug`."""
        self.unplugged.set()

    def replug(self, *, power_cycle: bool = True) -> None:
        """The base comes back after :meth:`unplug`.

        :param power_cycle: it was powered off: it has forgotten everything it was told, its counters
            are zero and its brake is set.
        """
        with self._lock:
            if power_cycle:
                self._power_on(brake=True)
            self._last_tick = None
            self._deframer.reset()
        self.unplugged.clear()

    # -- protocol ------------------------------------------------------------------------------
    def on_bytes(self, data: bytes) -> None:
        """Obey the host's commands in ``data``; a malformed or unknown one is counted in ``bad_commands``.

        :param data: the bytes read from the pty, in any pieces.
        """
        with self._lock:
            for packet in self._deframer.feed(data):
                self._received.append(packet)
                try:
                    self._handle(packet, time.monotonic())
                except (struct.error, IndexError):
                    self.bad_commands += 1

    def _handle(self, packet: Packet, now: float) -> None:
        key, data = (packet.port, packet.opcode), packet.data
        if key == (Port.MOT, Mot.SET_DIR):
            axis, vel, acc, torque, direction = struct.unpack('>BIIIB', data[:14])
            if axis in (0, 1):
                self._cmd_vel[axis] = vel if direction else -vel
                self._cmd_acc[axis], self._torque[axis] = acc, torque
        elif key == (Port.MOT, Mot.SET_POS):
            axis, _, _, _, pos = struct.unpack('>BIIIi', data[:17])
            if axis in (0, 1):
                self._pos[axis] = float(pos)
        elif key == (Port.MOT, Mot.SYSTEM_REPORT_REQ):
            period, mask = struct.unpack('>II', data[:8])
            self._report_period, self._report_mask = period / 1e6, mask
            self._next_report = now
        elif key == (Port.MOT, Mot.SET_DEFAULTS):
            self._cmd_vel = [0, 0]
        elif key == (Port.MOT, Mot.BRAKE_SET):
            self.brake = True
        elif key == (Port.MOT, Mot.BRAKE_RELEASE):
            self.brake = False
        elif key == (Port.SONAR, Sonar.RUN):
            self.sonar_on = data[12] != 0
            self._next_sonar = now
        elif key == (Port.DIO, Dio.REPORTS_REQ):
            (self.dio_period,) = struct.unpack('>I', data[:4])
        elif key == (Port.SYS, Sys.STATUS):
            raw = voltage_raw(self.voltage, self.robot.voltage_offset)
            self._send(codec.SystemStatus(self._f(raw), self.brake, self._stamp(now)))
        elif key == (Port.JSTK, Jstk.GET_STATE):
            x, y, buttons = self.joystick
            self._send(codec.JoystickState(self._f(x), self._f(y), buttons, self._stamp(now)))
        elif key != (Port.IR, Ir.RUN):
            self.bad_commands += 1

    def tick(self, now: float) -> None:
        """Move the axes, then send the DIO, motor, and sonar reports that are due.

        :param now: ``time.monotonic()`` of this turn.
        """
        with self._lock:
            last, self._last_tick = self._last_tick, now
            if last is not None:
                self._move(min(now - last, 0.1))
            if self.dio_period and self._dio_events:
                for address, value in self._dio_events:
                    self._send(codec.DioReport(address, self._f(value, 2), self._stamp(now)))
            self._dio_events.clear()
            if self._report_period > 0 and now >= self._next_report:
                self._next_report += self._report_period
                if self._next_report < now:
                    self._next_report = now + self._report_period
                self._send_motor_reports(now)
            if self.sonar_on and now >= self._next_sonar:
                self._next_sonar = now + self.sonar_period_s
                self._send_sonar(now)

    def _move(self, dt: float) -> None:
        for axis in (0, 1):
            target = 0.0 if self.brake else float(self._cmd_vel[axis])
            old, acc = self._vel[axis], float(self._cmd_acc[axis])
            step = target - old
            if acc > 0 and abs(step) > acc * dt:
                step = math.copysign(acc * dt, step)
            self._vel[axis] = old + step
            self._pos[axis] += (old + self._vel[axis]) / 2.0 * dt

    def _send_motor_reports(self, now: float) -> None:
        stamp = self._stamp(now)
        for axis in (0, 1):
            if self._report_mask & (1 << axis):
                self._send(codec.MotorReport(
                    axis, self._f(_wrap32(self._pos[axis])), self._f(_wrap32(self._vel[axis])),
                    self._f(self._cmd_acc[axis]), self._f(self._torque[axis]), stamp))
        self.motor_report_times.append(now)

    def _send_sonar(self, now: float) -> None:
        ranges = list(self.sonar_ranges()) if self.sonar_ranges is not None else []
        readings = []
        for index, pose in enumerate(self.robot.sonars):
            metres = ranges[index] if index < len(ranges) else math.inf
            readings.append((pose.sonar_id, self._f(sonar_range_raw(metres), 2)))
        for start in range(0, len(readings), 80):          # 8 + 3 * 80 bytes fit DLEN
            self._send(codec.SonarReport(tuple(readings[start:start + 80]), self._stamp(now)))

    # -- output ----------------------------------------------------------------------------------
    def _f(self, value: int, width: int = 4) -> int:
        """``value`` moved off any 0x1B byte unless the emulator stuffs."""
        return value if self.stuff_esc else codec.esc_free(value, width)

    def _stamp(self, now: float) -> int:
        return self._f(int((now - self._t0) * 1000) & 0xFFFFFFFF)

    def _send(self, report: codec.Report) -> None:
        for _ in range(256):
            self._packet_id = (self._packet_id + 1) & 0xFF
            packet = report.to_packet(self._packet_id)
            frame = codec.encode(packet, stuff=self.stuff_esc)
            if self.stuff_esc or codec.ESC not in frame[2:-2]:
                break
        if self._corrupt > 0:
            self._corrupt -= 1
            body = packet.body()
            bad = codec.crc(body) ^ 0x5A
            body += bytes((bad ^ 0x01 if bad == codec.ESC else bad,))
            if self.stuff_esc:
                body = body.replace(b'\x1b', b'\x1b\x00')
            frame = b'\x1b\x02' + body + b'\x1b\x03'
        if not self.silent.is_set():
            self.write(self.garbage + frame)
