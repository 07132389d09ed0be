"""Crossbow DMU serial protocol: command bytes, data packets, scale factors and a stream deframer.

Pure functions over bytes (no serial, no ROS); every bad input raises :class:`CodecError` only.

Where the facts come from (docs/protocols.md 7 and its "Additions", which give them in full):

- the commands, the packet layouts of scaled and angle mode and the scale factors are from a
  Crossbow DMU-family manual (the VG700M's; the DMU-6X/VGX manual itself was not found);
- ``R`` ping, ``r`` voltage mode, ``S`` serial number, the checksum (the sum of the bytes after
  the header, modulo 256) and the default 38400 baud are the family's convention (AHRS400
  sources), not confirmed in a DMU manual;
- *our assumptions*, to change here if a DMU manual says otherwise: the default ranges of
  :class:`DmuScale` (+-2 g, +-100 deg/s: Pluto's unit is unknown), the period of the time counter
  (:data:`TIME_TICK_S`), the serial-number reply (header, 4-byte big-endian number, checksum),
  and that the version string has no terminator.

Units after scaling are SI: rad, rad/s, m/s^2, degC.  Values are in the *sensor* frame (z down);
the device layer turns them into the robot frame.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import struct

from ..errors import CodecError
from .sample import Inertial

__all__ = [
    'CMD_ANGLE_MODE', 'CMD_CONTINUOUS', 'CMD_GET', 'CMD_PING', 'CMD_POLLED', 'CMD_SCALED_MODE',
    'CMD_SERIAL', 'CMD_VERSION', 'CMD_VOLTAGE_MODE', 'DEFAULT_BAUDRATE', 'G', 'HEADER',
    'REPLY_PING', 'REPLY_VOLTAGE_MODE', 'SERIAL_PACKET_LENGTH', 'TIME_TICK_S', 'DmuDeframer',
    'DmuMode', 'DmuPacket', 'DmuScale', 'checksum', 'decode_packet', 'decode_serial_number',
    'encode_packet', 'encode_serial_number', 'packet_length',
]

HEADER = 0xFF
DEFAULT_BAUDRATE = 38400
#: Standard gravity, m/s^2 (the sensor reports accelerations in g).
G = 9.80665
#: Seconds per count of the packet's 16-bit time word (ours: assumed, not from a DMU manual).
TIME_TICK_S = 0.79e-6

CMD_PING = b'R'
REPLY_PING = b'H'
CMD_VOLTAGE_MODE = b'r'
REPLY_VOLTAGE_MODE = b'R'
CMD_SCALED_MODE = b'c'
CMD_ANGLE_MODE = b'a'
CMD_POLLED = b'P'
CMD_CONTINUOUS = b'C'
CMD_GET = b'G'
CMD_VERSION = b'v'
CMD_SERIAL = b'S'

_FULL = 2 ** 15 - 1
SERIAL_PACKET_LENGTH = 6


class DmuMode(enum.Enum):
    """Measurement type; the value is the command byte, :attr:`reply` the byte the DMU answers."""

    SCALED = b'c'
    ANGLE = b'a'

    @property
    def command(self) -> bytes:
        return self.value

    @property
    def reply(self) -> bytes:
        return self.value.upper()


_WORDS = {DmuMode.SCALED: 8, DmuMode.ANGLE: 10}


def packet_length(mode: DmuMode) -> int:
    """Bytes in one data packet: header, the 16-bit words, checksum (18 scaled, 22 angle).

    :param mode: the measurement type.
    """
    return 2 + 2 * _WORDS[mode]


def checksum(body: bytes) -> int:
    """Sum of ``body`` modulo 256.

    :param body: the bytes after the header, before the checksum.
    """
    return sum(body) & 0xFF


@dataclasses.dataclass(frozen=True)
class DmuScale:
    """The unit's ranges, which set the scale of the rate and acceleration words.

    :param g_range: accelerometer range GR in g (ours: 2 by default).
    :param rate_range: rate-sensor range RR in deg/s (ours: 100 by default).
    """

    g_range: float = 2.0
    rate_range: float = 100.0

    def __post_init__(self) -> None:
        if not (self.g_range > 0 and self.rate_range > 0 and math.isfinite(self.g_range)
                and math.isfinite(self.rate_range)):
            raise CodecError(f'DMU ranges must be positive: {self}')

    @property
    def angle_lsb(self) -> float:
        """rad per count of an angle word."""
        return math.radians(180.0 / _FULL)

    @property
    def rate_lsb(self) -> float:
        """rad/s per count of a rate word."""
        return math.radians(self.rate_range * 1.5 / _FULL)

    @property
    def accel_lsb(self) -> float:
        """m/s^2 per count of an acceleration word."""
        return self.g_range * 1.5 / _FULL * G


def _temperature(word: int) -> float:
    return (word * 5.0 / 4096.0 - 1.375) * 44.44


def _temperature_word(celsius: float) -> int:
    return _clamp(round((celsius / 44.44 + 1.375) * 4096.0 / 5.0), 0, 0xFFFF)


def _clamp(value: int, low: int, high: int) -> int:
    return max(low, min(high, value))


def _word(value: float, lsb: float) -> int:
    """A signed word for ``value``, saturated like the sensor's output."""
    if not math.isfinite(value):
        raise CodecError(f'cannot encode non-finite value {value!r}')
    return _clamp(round(value / lsb), -0x8000, 0x7FFF)


@dataclasses.dataclass(frozen=True)
class _Moded:
    mode: DmuMode


@dataclasses.dataclass(frozen=True)
class DmuPacket(Inertial, _Moded):
    """One data packet in SI units, sensor frame (x forward, y right, z down: Pluto 8.2 says the
    sensor's z points down; y right follows for a right-handed frame with x forward).

    Fields in order: ``mode``, the :class:`~.sample.Inertial` fields (``roll`` and ``pitch`` are
    None in scaled mode: the packet has no angles), ``temperature`` (degC), ``time_ticks``.
    """

    temperature: float
    time_ticks: int


def encode_packet(packet: DmuPacket, scale: DmuScale = DmuScale()) -> bytes:
    """The bytes of ``packet`` (values are quantised and saturated as the sensor does).

    :param packet: SI units, sensor frame; its mode says which words are sent.
    :param scale: the unit's ranges, which scale the rate and acceleration words.
    :raises CodecError: a value is not finite, or angles are missing in angle mode.
    """
    words: list[int] = []
    if packet.mode is DmuMode.ANGLE:
        if packet.roll is None or packet.pitch is None:
            raise CodecError('an angle-mode packet needs roll and pitch')
        words += [_word(packet.roll, scale.angle_lsb), _word(packet.pitch, scale.angle_lsb)]
    words += [_word(v, scale.rate_lsb) for v in (packet.rate_x, packet.rate_y, packet.rate_z)]
    words += [_word(v, scale.accel_lsb) for v in (packet.accel_x, packet.accel_y, packet.accel_z)]
    if not math.isfinite(packet.temperature):
        raise CodecError(f'cannot encode temperature {packet.temperature!r}')
    body = struct.pack(f'>{len(words)}hHH', *words, _temperature_word(packet.temperature),
                       packet.time_ticks & 0xFFFF)
    return bytes([HEADER]) + body + bytes([checksum(body)])


def decode_packet(data: bytes, mode: DmuMode, scale: DmuScale = DmuScale()) -> DmuPacket:
    """The packet in ``data`` in SI units, sensor frame.

    :param data: exactly one packet of ``mode``, header to checksum.
    :param mode: the mode the unit is in (sets the length and the words).
    :param scale: the unit's ranges.
    :raises CodecError: wrong length, header or checksum.
    """
    length = packet_length(mode)
    if len(data) != length:
        raise CodecError(f'DMU {mode.name} packet must be {length} bytes, got {len(data)}')
    if data[0] != HEADER:
        raise CodecError(f'DMU packet header is 0x{data[0]:02X}, not 0xFF')
    body = bytes(data[1:-1])
    if checksum(body) != data[-1]:
        raise CodecError(f'DMU checksum 0x{data[-1]:02X} != 0x{checksum(body):02X}')
    n = _WORDS[mode] - 2
    *signed, temp_word, ticks = struct.unpack(f'>{n}hHH', body)
    roll = pitch = None
    if mode is DmuMode.ANGLE:
        roll, pitch = signed[0] * scale.angle_lsb, signed[1] * scale.angle_lsb
        signed = signed[2:]
    rate_x, rate_y, rate_z = (w * scale.rate_lsb for w in signed[0:3])
    accel_x, accel_y, accel_z = (w * scale.accel_lsb for w in signed[3:6])
    return DmuPacket(mode, roll, pitch, rate_x, rate_y, rate_z, accel_x, accel_y, accel_z,
                     _temperature(temp_word), ticks)


def encode_serial_number(number: int) -> bytes:
    """The reply to ``S`` (ours: header, 32-bit big-endian number, checksum).

    :param number: 0 to 2**32 - 1.
    :raises CodecError: a number that does not fit 32 bits.
    """
    if not 0 <= number <= 0xFFFFFFFF:
        raise CodecError(f'serial number {number} does not fit 32 bits')
    body = struct.pack('>I', number)
    return bytes([HEADER]) + body + bytes([checksum(body)])


def decode_serial_number(data: bytes) -> int:
    """The number in a reply to ``S``.

    :param data: exactly :data:`SERIAL_PACKET_LENGTH` bytes.
    :raises CodecError: wrong length, header or checksum.
    """
    if len(data) != SERIAL_PACKET_LENGTH or data[0] != HEADER:
        raise CodecError(f'not a DMU serial-number packet: {bytes(data).hex()}')
    body = bytes(data[1:-1])
    if checksum(body) != data[-1]:
        raise CodecError('DMU serial-number packet has a bad checksum')
    return int(struct.unpack('>I', body)[0])


class DmuDeframer:
    """Cuts a byte stream into data packets of one mode, resynchronising on the 0xFF header.

    Counters: :attr:`packets` decoded, :attr:`bad_checksum` candidate packets (a 0xFF and the
    bytes after it) whose checksum failed, :attr:`bytes_skipped` bytes dropped while looking for a
    header. An 8-bit sum cannot rule out a false start: a 0xFF in garbage followed by bytes whose
    sum happens to match (1 in 256) yields one wrong packet, after which sync is regained.
    """

    def __init__(self, mode: DmuMode, scale: DmuScale = DmuScale()) -> None:
        """Start with an empty buffer and zero counters.

        :param mode: the mode of every packet to find (sets their length).
        :param scale: the unit's ranges, for decoding.
        """
        self.mode = mode
        self.scale = scale
        self._length = packet_length(mode)
        self._buffer = bytearray()
        self.packets = 0
        self.bad_checksum = 0
        self.bytes_skipped = 0

    def reset(self) -> None:
        """Forget buffered bytes (counters are kept)."""
        self._buffer.clear()

    def feed(self, data: bytes) -> list[DmuPacket]:
        """Every complete packet that ``data`` completes, in order.

        :param data: bytes as read from the line; an unfinished packet is kept for the next call.
        """
        buffer = self._buffer
        buffer += data
        found: list[DmuPacket] = []
        while True:
            start = buffer.find(HEADER)
            if start < 0:
                self.bytes_skipped += len(buffer)
                buffer.clear()
                break
            if start:
                self.bytes_skipped += start
                del buffer[:start]
            if len(buffer) < self._length:
                break
            candidate = bytes(buffer[:self._length])
            if checksum(candidate[1:-1]) != candidate[-1]:
                self.bad_checksum += 1
                self.bytes_skipped += 1
                del buffer[:1]
                continue
            found.append(decode_packet(candidate, self.mode, self.scale))
            self.packets += 1
            del buffer[:self._length]
        return found
