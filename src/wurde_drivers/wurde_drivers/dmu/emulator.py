"""A Crossbow DMU on a pseudo-terminal: answers the single-character commands and streams packets.

The emulator speaks the protocol of :mod:`wurde_drivers.dmu.codec` in the **sensor's own frame**
(x forward, y right, z down); Pluto's dmuModule turns z up (Pluto Software Documentation 8.2),
and that conversion is the driver's job, not the emulator's.

Motion comes from ``motion_source(t) -> (roll, pitch, rate_x, rate_y, rate_z, accel_x, accel_y,
accel_z)`` in rad, rad/s and m/s^2, sensor frame, ``t`` in seconds since the emulator started.
The default is a unit lying still and level: the accelerometers read the specific force, so z
reads -g with z down (ours: the sign convention of a DMU at rest is assumed, not confirmed).

Behaviour (commands from the Crossbow manual, see the codec): power-up in angle mode, polled
(ours: assumed); ``G`` sends one packet and leaves continuous mode; in continuous mode packets
follow at ``rate_hz``, but never faster than the line can carry them (10 bits per byte). Input
at a baud rate other than the unit's is ignored, as a real UART would see only framing errors.

Faults: :meth:`inject_bad_checksums`, :meth:`inject_garbage`, :attr:`silent` (answers nothing,
streams nothing), :meth:`unplug` / :meth:`replug` (the unit vanishes; on return it has been power
cycled, so it is back in polled mode until the driver re-arms it).
"""

from __future__ import annotations

import math
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence

from ..ports.pty import PtyEmulator
from . import codec

MotionSource = Callable[[float], Sequence[float]]


def still_and_level(t: float) -> tuple[float, ...]:
    """The default motion source: not moving, level, gravity along +z (down) as -g.

    :param t: seconds since the emulator's first packet (unused).
    """
    return (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -codec.G)


class DmuEmulator(PtyEmulator):
    """The DMU at the far end of a pty; open :attr:`path` at 38400 baud."""

    def __init__(self, *, motion_source: MotionSource = still_and_level, rate_hz: float = 100.0,
                 baudrate: int = codec.DEFAULT_BAUDRATE,
                 rate_bias: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 scale: codec.DmuScale = codec.DmuScale(), temperature: float = 25.0,
                 version: str = 'DMU-VGX emulator 1.0', serial_number: int = 9900123,
                 tick_s: float = 0.002) -> None:
        """Open the pty and power up (angle mode, polled); :meth:`start` runs it.

        :param motion_source: ``t -> (roll, pitch, rate_x, rate_y, rate_z, accel_x, accel_y, accel_z)``
            in rad, rad/s and m/s², sensor frame, ``t`` in seconds since the first packet.
        :param rate_hz: packets per second in continuous mode (capped by the baud rate).
        :param baudrate: the unit's line speed; input at any other speed is ignored.
        :param rate_bias: constant bias (rad/s) added to the x, y, z rates, sensor frame.
        :param scale: the unit's ranges.
        :param temperature: degC reported in every packet.
        :param version: the reply to ``v``.
        :param serial_number: the number in the reply to ``S``.
        :param tick_s: seconds between two turns of the emulator's thread.
        :raises ValueError: ``rate_hz`` not positive.
        """
        super().__init__(tick_s=tick_s)
        if not rate_hz > 0:
            raise ValueError(f'rate_hz must be positive, got {rate_hz}')
        self.motion_source = motion_source
        self.unit_baudrate = baudrate
        self.rate_bias = rate_bias
        self.scale = scale
        self.temperature = temperature
        self.version = version
        self.serial_number = serial_number
        self._requested_hz = rate_hz
        self._lock = threading.Lock()
        self._t0: float | None = None
        self._next_due = 0.0
        self._bad_checksums = 0
        self._garbage = b''
        #: While set, the unit answers nothing and streams nothing (but stays plugged in).
        self.silent = threading.Event()
        self.packets_sent = 0
        #: The last command bytes received, oldest first.
        self.commands: deque[bytes] = deque(maxlen=256)
        self._power_up()

    # -- state --------------------------------------------------------------------------------
    def _power_up(self) -> None:
        self.mode = codec.DmuMode.ANGLE
        self.continuous = False

    @property
    def period(self) -> float:
        """Seconds between two packets in continuous mode (the line's limit included)."""
        line_limit = codec.packet_length(self.mode) * 10.0 / self.unit_baudrate
        return max(1.0 / self._requested_hz, line_limit)

    def _line_ok(self) -> bool:
        speed = self.baudrate
        return speed in (0, self.unit_baudrate)

    # -- faults -------------------------------------------------------------------------------
    def inject_bad_checksums(self, count: int = 1) -> None:
        """Corrupt the checksum of the next ``count`` packets.

        :param count: how many; added to any still pending.
        """
        with self._lock:
            self._bad_checksums += count

    def inject_garbage(self, data: bytes) -> None:
        """Send ``data`` before the next packet (or at once when polled).

        :param data: the garbage bytes; added to any still pending.
        """
        with self._lock:
            self._garbage += data

    def unplug(self) -> None:
        """The unit vanishes: nothing is read or written."""
        self.unplugged.set()

    def replug(self) -> None:
        """The unit returns, power cycled: angle mode, polled."""
        with self._lock:
            self._power_up()
        self.unplugged.clear()

    # -- protocol -----------------------------------------------------------------------------
    def packet(self, now: float) -> bytes:
        """The packet the unit would send at monotonic time ``now``.

        :param now: ``time.monotonic()``; the first call sets the motion source's time 0.
        """
        if self._t0 is None:
            self._t0 = now
        t = now - self._t0
        roll, pitch, rx, ry, rz, ax, ay, az = (float(v) for v in self.motion_source(t))
        bx, by, bz = self.rate_bias
        angle = self.mode is codec.DmuMode.ANGLE
        packet = codec.DmuPacket(self.mode, roll if angle else None, pitch if angle else None,
                                 rx + bx, ry + by, rz + bz, ax, ay, az, self.temperature,
                                 int(t / codec.TIME_TICK_S) & 0xFFFF)
        data = codec.encode_packet(packet, self.scale)
        if self._bad_checksums:
            self._bad_checksums -= 1
            data = data[:-1] + bytes([(data[-1] + 1) & 0xFF])
        return data

    def _send_packet(self, now: float) -> None:
        with self._lock:
            out = self._garbage + self.packet(now)
            self._garbage = b''
        self.write(out)
        self.packets_sent += 1

    def on_bytes(self, data: bytes) -> None:
        """Obey each command byte in ``data``; ignored while silent or at the wrong line speed.

        :param data: the bytes read from the pty; unknown bytes are ignored, as a real unit does.
        """
        if self.silent.is_set() or not self._line_ok():
            return
        now = time.monotonic()
        for value in data:
            command = bytes([value])
            self.commands.append(command)
            self._command(command, now)

    def _command(self, command: bytes, now: float) -> None:
        if command == codec.CMD_PING:
            self.write(codec.REPLY_PING)
        elif command == codec.CMD_VOLTAGE_MODE:
            self.write(codec.REPLY_VOLTAGE_MODE)  # acknowledged; voltage packets are not emulated
        elif command in (codec.CMD_SCALED_MODE, codec.CMD_ANGLE_MODE):
            with self._lock:
                self.mode = codec.DmuMode(command)
            self.write(self.mode.reply)
        elif command == codec.CMD_POLLED:
            self.continuous = False
        elif command == codec.CMD_CONTINUOUS:
            self.continuous = True
            self._next_due = now
        elif command == codec.CMD_GET:
            self.continuous = False
            self._send_packet(now)
        elif command == codec.CMD_VERSION:
            self.write(self.version.encode('ascii'))
        elif command == codec.CMD_SERIAL:
            self.write(codec.encode_serial_number(self.serial_number))
        # anything else: a real unit ignores unknown bytes

    def tick(self, now: float) -> None:
        """Send the next packet in continuous mode when it is due (pending garbage when polled).

        :param now: ``time.monotonic()`` of this turn.
        """
        if self.silent.is_set() or not self._line_ok():
            return
        if not self.continuous:
            if self._garbage:
                with self._lock:
                    out, self._garbage = self._garbage, b''
                self.write(out)
            return
        if now < self._next_due:
            return
        self._send_packet(now)
        period = self.period
        self._next_due += period
        if self._next_due < now - period:  # fell behind (a stalled thread): do not burst
            self._next_due = now + period


def constant_rate(rate_z: float, *, roll: float = 0.0, pitch: float = 0.0) -> MotionSource:
    """A motion source turning about the sensor's z axis (down); the accelerometers see gravity only.

    :param rate_z: rad/s about z down (negative: counter-clockwise seen from above).
    :param roll: the constant tilt about x, rad.
    :param pitch: the constant tilt about y, rad.
    """
    # specific force at rest in the body axes of a z-down frame:
    # f = g * (sin p, -sin r cos p, -cos r cos p)
    gx = codec.G * math.sin(pitch)
    gy = -codec.G * math.sin(roll) * math.cos(pitch)
    gz = -codec.G * math.cos(roll) * math.cos(pitch)

    def source(t: float) -> tuple[float, ...]:
        return (roll, pitch, 0.0, 0.0, rate_z, gx, gy, gz)
    return source
