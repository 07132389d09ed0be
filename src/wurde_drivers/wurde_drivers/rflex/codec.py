"""rFLEX (iRobot/RWI B21r, ATRV-Jr base controller) codec: frames, deframer, commands, reports.

Frame (docs/protocols.md 3)::

    ESC STX | PORT | ID | OPCODE | DLEN | DATA[DLEN] | CRC | ESC ETX      (ESC=1B STX=02 ETX=03)

``CRC`` is the XOR of PORT..DATA; multi-byte fields are big-endian. The sources disagree on byte
stuffing: Player and CARMEN never stuff, DLu's reader un-stuffs ``1B 00`` to ``1B`` and drops
``1B 01``. :class:`Deframer` reads both kinds of sender: it un-stuffs like DLu, keeps an ESC that
is followed by any other byte as a raw data byte (an unstuffed sender), resynchronises on every
``ESC STX`` and checks length, CRC and ``ESC ETX``. :func:`encode` stuffs only when asked.

Pure functions over bytes: bad input raises :class:`CodecError` and nothing else.
"""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Iterator

from typing import ClassVar, Union

from ..errors import CodecError

__all__ = [
    'ESC', 'STX', 'ETX', 'NUL', 'SOH', 'Port', 'Sys', 'Mot', 'Sonar', 'Dio', 'Ir', 'Jstk',
    'Packet', 'crc', 'encode', 'decode', 'Deframer', 'esc_free', 'esc_free_set_dir',
    'set_dir', 'set_pos', 'system_report_req', 'set_defaults', 'brake_set', 'brake_release',
    'sonar_run', 'dio_reports_req', 'ir_run', 'sys_status_poll', 'jstk_poll',
    'DioReport', 'JoystickState', 'MotorReport', 'Report', 'SonarReport', 'SystemStatus',
    'decode_report', 'TRANS_AXIS', 'ROT_AXIS',
]

ESC, STX, ETX, NUL, SOH = 0x1B, 0x02, 0x03, 0x00, 0x01
#: Largest body after un-stuffing: PORT ID OPCODE DLEN + 255 data bytes + CRC.
_MAX_BODY = 4 + 255 + 1
TRANS_AXIS, ROT_AXIS = 0, 1


class Port:
    """Port numbers (rflex-info.h)."""
    SYS, MOT, JSTK, SONAR, DIO, IR = 1, 2, 3, 4, 5, 6


class Sys:
    LCD_DUMP, STATUS = 0, 1


class Mot:
    AXIS_GET_SYSTEM, GET_MODEL, GET_TARGET, SET_DIR, SET_POS, GET_MODE = 0, 1, 2, 7, 8, 9
    SET_DEFAULTS, BRAKE_SET, BRAKE_RELEASE, SYSTEM_REPORT, SYSTEM_REPORT_REQ = 10, 11, 12, 33, 34


class Sonar:
    RUN, GET_UPDATE, REPORT = 0, 1, 2


class Dio:
    REPORTS_REQ, REPORT, GET_UPDATE, UPDATE, SET = 0, 1, 2, 3, 4


class Ir:
    RUN, REPORT = 0, 1


class Jstk:
    GET_STATE = 0


@dataclasses.dataclass(frozen=True)
class Packet:
    """One rFLEX packet: the header fields and the (un-stuffed) data."""

    port: int
    packet_id: int
    opcode: int
    data: bytes = b''

    def __post_init__(self) -> None:
        for name in ('port', 'packet_id', 'opcode'):
            value = getattr(self, name)
            if not isinstance(value, int) or not 0 <= value <= 0xFF:
                raise CodecError(f'rFLEX {name} {value!r} is not a byte')
        if len(self.data) > 255:
            raise CodecError(f'rFLEX data of {len(self.data)} bytes does not fit DLEN (255)')
        object.__setattr__(self, 'data', bytes(self.data))

    def body(self) -> bytes:
        """PORT ID OPCODE DLEN DATA (what the CRC covers)."""
        return bytes((self.port, self.packet_id, self.opcode, len(self.data))) + self.data


def crc(body: bytes) -> int:
    """XOR of ``body`` (PORT..DATA), as ``computeCRC`` in every source.

    :param body: PORT, ID, OPCODE, DLEN and DATA, un-stuffed.
    """
    value = 0
    for byte in body:
        value ^= byte
    return value


def encode(packet: Packet, *, stuff: bool = False) -> bytes:
    """The frame of ``packet``, ``ESC STX`` to ``ESC ETX``.

    :param packet: the packet to send.
    :param stuff: send every 0x1B of PORT..CRC as ``1B 00`` (DLu's reader); False sends the bytes as
        they are (Player and CARMEN).
    """
    body = packet.body()
    body += bytes((crc(body),))
    if stuff:
        body = body.replace(b'\x1b', b'\x1b\x00')
    return b'\x1b\x02' + body + b'\x1b\x03'


def _check_body(body: bytes) -> Packet:
    """Length and CRC of an un-stuffed PORT..CRC body; :raises CodecError:."""
    if len(body) < 5:
        raise CodecError(f'rFLEX frame too short ({len(body)} bytes between STX and ETX)')
    if len(body) != body[3] + 5:
        raise CodecError(f'rFLEX DLEN {body[3]} does not match {len(body) - 5} data bytes')
    if crc(body[:-1]) != body[-1]:
        raise _BadCrc(f'rFLEX CRC {body[-1]:#04x} != {crc(body[:-1]):#04x}')
    return Packet(body[0], body[1], body[2], body[4:-1])


class _BadCrc(CodecError):
    """A frame intact in length whose CRC does not match (counted apart by the deframer)."""


def decode(frame: bytes) -> Packet:
    """One complete frame (stuffed or not) back to its :class:`Packet`.

    :param frame: exactly one frame, ``ESC STX`` to ``ESC ETX``.
    :raises CodecError: bad delimiters, a wrong length or CRC, or stray bytes.
    """
    frame = bytes(frame)
    if len(frame) < 9 or frame[:2] != b'\x1b\x02' or frame[-2:] != b'\x1b\x03':
        raise CodecError('rFLEX frame must start with ESC STX and end with ESC ETX')
    deframer = Deframer()
    packets = deframer.feed(frame)
    if len(packets) != 1 or deframer.bytes_skipped or deframer.in_frame:
        raise CodecError(f'rFLEX frame is malformed: {deframer.last_error or "stray bytes"}')
    return packets[0]


class Deframer:
    """Stream deframer: ``feed(bytes) -> list[Packet]``; never raises on bad bytes.

    Counters: ``packets`` (good frames), ``bad_crc`` (dropped), ``bad_frames`` (wrong length,
    overlong, cut by a new ``ESC STX``), ``bytes_skipped`` (garbage outside frames and the bytes
    of bad frames). ``last_error`` says why the last frame was refused.
    """

    def __init__(self) -> None:
        self.packets = 0
        self.bad_crc = 0
        self.bad_frames = 0
        self.bytes_skipped = 0
        self.last_error = ''
        self.in_frame = False
        self._esc = False           # the previous byte was an ESC not yet interpreted
        self._body = bytearray()
        self._raw = 0               # bytes of the current frame as received (for counting)

    def reset(self) -> None:
        """Forget any partial frame (e.g. after the port was reopened); counters stay."""
        self.bytes_skipped += self._raw if self.in_frame else int(self._esc)
        self.in_frame = self._esc = False
        self._body.clear()
        self._raw = 0

    def feed(self, data: bytes) -> list[Packet]:
        """The packets completed by ``data`` (any chunking); partial frames are kept.

        :param data: bytes as read from the line.
        :returns: the good packets, in order; bad frames and garbage are only counted.
        """
        return list(self._feed(data))

    def _refuse(self, reason: str) -> None:
        self.bad_frames += 1
        self.bytes_skipped += self._raw
        self.last_error = reason
        self.in_frame = False
        self._body.clear()
        self._raw = 0

    def _start(self) -> None:
        self.in_frame = True
        self._body.clear()
        self._raw = 2

    def _feed(self, data: bytes) -> Iterator[Packet]:
        for byte in data:
            if not self.in_frame:
                if self._esc:
                    if byte == STX:
                        self._esc = False
                        self._start()
                        continue
                    self.bytes_skipped += 1          # the ESC that started no frame
                    self._esc = byte == ESC
                    if not self._esc:
                        self.bytes_skipped += 1
                elif byte == ESC:
                    self._esc = True
                else:
                    self.bytes_skipped += 1
                continue
            self._raw += 1
            if self._esc:
                self._esc = False
                if byte == NUL:
                    self._append(ESC)
                elif byte == SOH:
                    pass
                elif byte == STX:
                    self._raw -= 2
                    self._refuse('frame cut by a new ESC STX')
                    self._start()
                elif byte == ETX:
                    packet = self._finish()
                    if packet is not None:
                        yield packet
                else:                                # an unstuffed sender's raw 0x1B
                    self._append(ESC)
                    if byte == ESC:
                        self._esc = True
                    else:
                        self._append(byte)
            elif byte == ESC:
                self._esc = True
            else:
                self._append(byte)

    def _append(self, byte: int) -> None:
        if not self.in_frame:
            return
        self._body.append(byte)
        limit = self._body[3] + 5 if len(self._body) > 3 else _MAX_BODY
        if len(self._body) > limit:
            self._refuse(f'no ESC ETX after DLEN {self._body[3]} data bytes')
            self._esc = False

    def _finish(self) -> Packet | None:
        body, raw = bytes(self._body), self._raw
        self.in_frame = False
        self._body.clear()
        self._raw = 0
        try:
            packet = _check_body(body)
        except _BadCrc as error:
            self.bad_crc += 1
            self.last_error = str(error)
            return None
        except CodecError as error:
            self._raw = raw
            self._refuse(str(error))
            return None
        self.packets += 1
        return packet


# -- the 0x1B workaround ------------------------------------------------------------------------
def esc_free(value: int, width: int = 4) -> int:
    """The value nearest to ``value`` whose ``width`` big-endian bytes hold no 0x1B.

    Player's "hardware bug" workaround (``rflex_set_velocity``, docs/protocols.md 3) rounds a
    rotational velocity whose second or fourth byte is 0x1B to the nearest 0x1C00.. or 0x1AFF..;
    this applies the same rule to every byte, highest first (for the lowest byte, down to 0x1A).

    :param value: the field's value; may be negative (two's complement), and the result has the
        same sign.
    :param width: the field's size in bytes.
    """
    mask = (1 << (8 * width)) - 1
    raw = value & mask
    for shift in range(8 * (width - 1), -1, -8):
        if (raw >> shift) & 0xFF != ESC:
            continue
        below = (1 << shift) - 1
        lower = (raw >> (shift - 8)) & 0xFF if shift else 0
        high = raw & ~((0xFF << shift) | below) & mask
        raw = high | (0x1C << shift) if lower > 127 else high | (0x1A << shift) | below
    if value < 0:
        raw -= mask + 1
    return raw


def esc_free_set_dir(axis: int, velocity: int, acceleration: int, torque: int,
                     direction: int) -> Packet:
    """A SET_DIR packet whose data and CRC hold no 0x1B (what the driver sends).

    Should the CRC still come out as 0x1B, the acceleration is moved by one count (harmless)
    rather than the velocity.

    :param axis: 0 translation, 1 rotation.
    :param velocity: |velocity| in counts/s, moved off 0x1B bytes by :func:`esc_free`.
    :param acceleration: counts/s², moved off 0x1B bytes likewise.
    :param torque: the axis' torque (Player: 30000 translation, 35000 rotation).
    :param direction: 1 forward (v >= 0), 0 backward.
    """
    velocity = esc_free(velocity)
    base = esc_free(acceleration)
    for step in (0, 1, -1, 2, -2, 3, -3):
        acc = base + step
        if acc < 0 or esc_free(acc) != acc:
            continue
        packet = set_dir(axis, velocity, acc, torque, direction)
        if ESC not in encode(packet)[2:-2]:
            return packet
    raise CodecError(f'no ESC-free SET_DIR for velocity {velocity}')  # unreachable in practice


# -- host commands (docs/protocols.md 3, "Host -> base payloads") ----------------------------------
def _u32(*values: int) -> bytes:
    try:
        return struct.pack(f'>{len(values)}I', *values)
    except struct.error as error:
        raise CodecError(f'rFLEX field out of range: {values}') from error


def _u8(value: int) -> bytes:
    if not 0 <= value <= 0xFF:
        raise CodecError(f'rFLEX byte field out of range: {value}')
    return bytes((value,))


def set_dir(axis: int, velocity: int, acceleration: int, torque: int, direction: int) -> Packet:
    """MOT_AXIS_SET_DIR: a velocity magnitude and a direction bit for one axis.

    :param axis: 0 translation, 1 rotation.
    :param velocity: |velocity| in counts/s.
    :param acceleration: counts/s².
    :param torque: the axis' torque (Player: 30000 translation, 35000 rotation).
    :param direction: 1 forward (v >= 0), 0 backward.
    :raises CodecError: a field that does not fit its unsigned width.
    """
    data = _u8(axis) + _u32(velocity, acceleration, torque) + _u8(direction)
    return Packet(Port.MOT, 0, Mot.SET_DIR, data)


def set_pos(axis: int, velocity: int, acceleration: int, torque: int, position: int) -> Packet:
    """MOT_AXIS_SET_POS (CARMEN uses it to reset a counter).

    :param axis: 0 distance, 1 bearing.
    :param velocity: counts/s.
    :param acceleration: counts/s².
    :param torque: the axis' torque.
    :param position: the counter's new value, signed 32-bit.
    """
    data = _u8(axis) + _u32(velocity, acceleration, torque) + _u32(position & 0xFFFFFFFF)
    return Packet(Port.MOT, 0, Mot.SET_POS, data)


def system_report_req(period_us: int, mask: int = 3) -> Packet:
    """MOT_SYSTEM_REPORT_REQ: one MOT_SYSTEM_REPORT per axis in ``mask`` every ``period_us``.

    :param period_us: microseconds between reports (Player and CARMEN: 100000); 0 with mask 0
        turns them off.
    :param mask: bit per axis (3: axes 0 and 1).
    """
    return Packet(Port.MOT, 0, Mot.SYSTEM_REPORT_REQ, _u32(period_us, mask))


def set_defaults() -> Packet:
    return Packet(Port.MOT, 0, Mot.SET_DEFAULTS)


def brake_set() -> Packet:
    return Packet(Port.MOT, 0, Mot.BRAKE_SET)


def brake_release() -> Packet:
    return Packet(Port.MOT, 0, Mot.BRAKE_RELEASE)


def sonar_run(on: bool, echo_delay: int = 30000, ping_delay: int = 0,
              set_delay: int = 0) -> Packet:
    """SONAR_RUN (ID 4): mode 2 runs the sonars; off sends zeros.

    :param on: run the sonars (mode 2) or stop them (13 zero bytes).
    :param echo_delay: the first 32-bit field, as the sources send it (30000).
    :param ping_delay: the second field (0).
    :param set_delay: the third field (0).
    """
    data = _u32(echo_delay, ping_delay, set_delay) + b'\x02' if on else bytes(13)
    return Packet(Port.SONAR, 4, Sonar.RUN, data)


def dio_reports_req(period: int) -> Packet:
    """DIO_REPORTS_REQ; hosts send ID 0 to turn reports on and ID 4 to turn them off.

    :param period: the report period as the sources send it; 0 turns the reports off.
    """
    return Packet(Port.DIO, 0 if period else 4, Dio.REPORTS_REQ, _u32(period))


def ir_run(on: bool) -> Packet:
    """IR_RUN: ``0, 70, 10, 20, 150`` and run 2, or all zeros.

    :param on: run the infrared sensors, or stop them.
    """
    data = _u32(0, 70, 10, 20, 150) + b'\x02' if on else bytes(21)
    return Packet(Port.IR, 0, Ir.RUN, data)


def sys_status_poll() -> Packet:
    """SYS_STATUS poll; the base answers with :class:`SystemStatus`."""
    return Packet(Port.SYS, 0, Sys.STATUS)


def jstk_poll() -> Packet:
    """JSTK_GET_STATE poll; the base answers with :class:`JoystickState`."""
    return Packet(Port.JSTK, 0, Jstk.GET_STATE)


# -- base reports (docs/protocols.md 3, "Base -> host reports") ------------------------------------
def _pack(fmt: str, *values: int) -> bytes:
    try:
        return struct.pack(fmt, *values)
    except struct.error as error:
        raise CodecError(f'rFLEX report field out of range: {values}') from error


def _need(packet: Packet, size: int, what: str) -> None:
    if len(packet.data) < size:
        raise CodecError(f'rFLEX {what} needs {size} data bytes, got {len(packet.data)}')


@dataclasses.dataclass(frozen=True)
class MotorReport:
    """MOT_SYSTEM_REPORT, one per axis: axis 0 position = distance, axis 1 = bearing (counts)."""

    axis: int
    position: int
    velocity: int
    acceleration: int = 0
    torque: int = 0
    timestamp: int = 0
    rv: int = 0
    KEY: ClassVar[tuple[int, int]] = (Port.MOT, Mot.SYSTEM_REPORT)
    _FMT: ClassVar[str] = '>iIBiiii'

    def to_packet(self, packet_id: int = 0) -> Packet:
        """This report as the base sends it (the emulator's side).

        :param packet_id: the packet's ID byte (base reports carry increasing IDs).
        """
        return Packet(Port.MOT, packet_id, Mot.SYSTEM_REPORT, _pack(
            self._FMT, self.rv, self.timestamp, self.axis, self.position, self.velocity,
            self.acceleration, self.torque))

    @classmethod
    def from_packet(cls, packet: Packet) -> 'MotorReport':
        """The report in a MOT_SYSTEM_REPORT packet.

        :param packet: a packet of port MOT, opcode SYSTEM_REPORT.
        :raises CodecError: fewer than 25 data bytes.
        """
        _need(packet, 25, 'MOT_SYSTEM_REPORT')
        rv, stamp, axis, pos, vel, acc, trq = struct.unpack_from(cls._FMT, packet.data)
        return cls(axis, pos, vel, acc, trq, stamp, rv)


@dataclasses.dataclass(frozen=True)
class SystemStatus:
    """SYS_STATUS reply: raw voltage (volts = raw / 100 + offset, see rflex.robots) and brake."""

    voltage_raw: int
    brake: bool
    timestamp: int = 0
    KEY: ClassVar[tuple[int, int]] = (Port.SYS, Sys.STATUS)

    def to_packet(self, packet_id: int = 0) -> Packet:
        """This reply as the base sends it (the emulator's side).

        :param packet_id: the packet's ID byte.
        """
        return Packet(Port.SYS, packet_id, Sys.STATUS,
                      _pack('>IIB', self.timestamp, self.voltage_raw, int(self.brake)))

    @classmethod
    def from_packet(cls, packet: Packet) -> 'SystemStatus':
        """The reply in a SYS_STATUS packet.

        :param packet: a packet of port SYS, opcode STATUS.
        :raises CodecError: fewer than 9 data bytes.
        """
        _need(packet, 9, 'SYS_STATUS reply')
        stamp, voltage, brake = struct.unpack_from('>IIB', packet.data)
        return cls(voltage, bool(brake), stamp)


@dataclasses.dataclass(frozen=True)
class DioReport:
    """DIO_REPORT: a digital input changed (B21r bumpers at 0x40-0x4D, heading home 0x31)."""

    address: int
    value: int
    timestamp: int = 0
    KEY: ClassVar[tuple[int, int]] = (Port.DIO, Dio.REPORT)

    def to_packet(self, packet_id: int = 0) -> Packet:
        """This report as the base sends it (the emulator's side).

        :param packet_id: the packet's ID byte.
        """
        return Packet(Port.DIO, packet_id, Dio.REPORT,
                      _pack('>IBH', self.timestamp, self.address, self.value))

    @classmethod
    def from_packet(cls, packet: Packet) -> 'DioReport':
        """The report in a DIO_REPORT packet.

        :param packet: a packet of port DIO, opcode REPORT.
        :raises CodecError: fewer than 7 data bytes.
        """
        _need(packet, 7, 'DIO_REPORT')
        stamp, address, value = struct.unpack_from('>IBH', packet.data)
        return cls(address, value, stamp)


@dataclasses.dataclass(frozen=True)
class SonarReport:
    """SONAR_REPORT: ``(sonar id, raw range)`` triplets; 1476 units per metre, 32766 = no echo.

    The protocol text says "/2", but every driver reads 3-byte triplets (docs/protocols.md 3).
    """

    readings: tuple[tuple[int, int], ...]
    timestamp: int = 0
    retval: int = 0
    KEY: ClassVar[tuple[int, int]] = (Port.SONAR, Sonar.REPORT)

    def to_packet(self, packet_id: int = 0) -> Packet:
        """This report as the base sends it (the emulator's side).

        :param packet_id: the packet's ID byte.
        """
        data = _pack('>II', self.retval, self.timestamp)
        data += b''.join(_pack('>BH', sid, rng) for sid, rng in self.readings)
        return Packet(Port.SONAR, packet_id, Sonar.REPORT, data)

    @classmethod
    def from_packet(cls, packet: Packet) -> 'SonarReport':
        """The readings in a SONAR_REPORT packet.

        :param packet: a packet of port SONAR, opcode REPORT.
        :raises CodecError: fewer than 8 data bytes, or a tail that is not whole triplets.
        """
        _need(packet, 8, 'SONAR_REPORT')
        if (len(packet.data) - 8) % 3:
            raise CodecError(f'SONAR_REPORT of {len(packet.data)} bytes is not 8 + 3n')
        retval, stamp = struct.unpack_from('>II', packet.data)
        readings = tuple(struct.iter_unpack('>BH', packet.data[8:]))
        return cls(readings, stamp, retval)


@dataclasses.dataclass(frozen=True)
class JoystickState:
    """JSTK_GET_STATE reply: x at data[4..7], y at data[8..11], buttons at data[12]."""

    x: int
    y: int
    buttons: int
    timestamp: int = 0
    KEY: ClassVar[tuple[int, int]] = (Port.JSTK, Jstk.GET_STATE)

    def to_packet(self, packet_id: int = 0) -> Packet:
        """This reply as the base sends it (the emulator's side).

        :param packet_id: the packet's ID byte.
        """
        return Packet(Port.JSTK, packet_id, Jstk.GET_STATE,
                      _pack('>IiiB', self.timestamp, self.x, self.y, self.buttons))

    @classmethod
    def from_packet(cls, packet: Packet) -> 'JoystickState':
        """The state in a JSTK_GET_STATE reply.

        :param packet: a packet of port JSTK, opcode GET_STATE.
        :raises CodecError: fewer than 13 data bytes.
        """
        _need(packet, 13, 'JSTK state')
        stamp, x, y, buttons = struct.unpack_from('>IiiB', packet.data)
        return cls(x, y, buttons, stamp)


Report = Union[MotorReport, SystemStatus, DioReport, SonarReport, JoystickState]
_REPORTS = {cls.KEY: cls for cls in (MotorReport, SystemStatus, DioReport, SonarReport,
                                      JoystickState)}


def decode_report(packet: Packet) -> Report | Packet:
    """The report a base packet carries; a packet of another kind comes back unchanged.

    :param packet: a packet from the base.
    :raises CodecError: a known report whose data is too short or malformed.
    """
    cls = _REPORTS.get((packet.port, packet.opcode))
    return packet if cls is None else cls.from_packet(packet)
