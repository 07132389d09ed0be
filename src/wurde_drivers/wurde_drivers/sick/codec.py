"""SICK LMS 2xx / PLS telegrams: CRC, framing, a stream deframer, requests and replies.

Pure functions over bytes (docs/design.md "Drivers"); every fact here is from docs/protocols.md section 1:
frame ``STX ADR LEN_lo LEN_hi CMD DATA.. [STATUS] CRC_lo CRC_hi`` (1.2), the SICK CRC-16 (1.3),
lone ACK/NAK bytes (1.4), the request table (1.5) and the B0 measurement reply (1.6).
Bad input raises :class:`~wurde_drivers.errors.CodecError` and nothing else.
"""

from __future__ import annotations

import dataclasses
import math
import struct
from collections.abc import Sequence
from typing import ClassVar

from ..errors import CodecError

STX = 0x02
ACK = 0x06
NAK = 0x15
HOST_ADDRESS = 0x00     #: ADR of frames the host sends
DEVICE_ADDRESS = 0x80   #: ADR of frames an LMS at address 0 sends
MAX_PAYLOAD = 812       #: largest LEN (CMD + DATA + STATUS)

#: Request command codes (reply = request + 0x80, docs/protocols.md 1.4).
CMD_RESET, CMD_MODE, CMD_SCAN, CMD_STATUS = 0x10, 0x20, 0x30, 0x31
CMD_TYPE, CMD_VARIANT, CMD_READ_CONFIG, CMD_WRITE_CONFIG = 0x3A, 0x3B, 0x74, 0x77
#: Reply codes.  0x90 (power-on) and 0x91 (reset acknowledged) belong to our reset sequence.
REPLY_POWER_ON, REPLY_RESET, REPLY_NOT_ACK = 0x90, 0x91, 0x92
REPLY_MODE, REPLY_SCAN, REPLY_STATUS, REPLY_TYPE = 0xA0, 0xB0, 0xB1, 0xBA
REPLY_VARIANT, REPLY_READ_CONFIG, REPLY_WRITE_CONFIG = 0xBB, 0xF4, 0xF7

#: Operating modes of request 0x20.
MODE_INSTALL, MODE_CONTINUOUS, MODE_ON_REQUEST = 0x00, 0x24, 0x25
#: Baud rate → mode code of request 0x20 (sicktoolbox enum, docs/protocols.md 1.5).
BAUD_CODES = {9600: 0x42, 19200: 0x41, 38400: 0x40, 500000: 0x48}
BAUD_BY_CODE = {code: baud for baud, code in BAUD_CODES.items()}
PASSWORDS = {'LMS': b'SICK_LMS', 'PLS': b'SICK_PLS'}

#: Units of the B0 count word (bits 14-15) and of config byte [6]; metres per raw unit.
UNIT_SCALE = {'cm': 0.01, 'mm': 0.001, '10cm': 0.1}
_UNIT_BITS = {'cm': 0, 'mm': 1, '10cm': 2}
_CONFIG_UNITS = {0: 'cm', 1: 'mm', 2: '10cm'}

#: Error codes carried in a 13-bit value (sicktoolbox_wrapper, telegram listing p.124).
RANGE_MASK = 0x1FFF
VALUE_TOO_FAR = 8183
ERROR_CODES = {8191: 'not valid', 8190: 'dazzling', 8189: 'operation overflow',
               8188: 'undocumented error code', 8187: 'SNR too small',
               8186: 'channel-1 read error', 8185: 'undocumented error code',
               8184: 'undocumented error code', 8183: 'value > maximum'}
STATUS_SIZE = 123       #: data bytes we send in a B1 reply (payload 124 with the command)


def sick_crc16(buf: bytes | bytearray | memoryview) -> int:
    """The SICK CRC-16 (poly 0x8005, init 0, each byte mixed with the previous one; 1.3).

    :param buf: the frame from STX up to, not including, the two CRC bytes.
    :returns: the 16-bit CRC, sent low byte first.
    """
    crc, prev = 0, 0
    for byte in bytes(buf):
        if crc & 0x8000:
            crc = ((crc & 0x7FFF) << 1) ^ 0x8005
        else:
            crc = (crc << 1) & 0xFFFF
        crc ^= byte | (prev << 8)
        prev = byte
    return crc


@dataclasses.dataclass(frozen=True)
class Telegram:
    """One frame; device frames (``address & 0x80``) carry a STATUS byte, host frames none."""

    address: int
    command: int
    data: bytes = b''
    status: int | None = None

    @property
    def from_device(self) -> bool:
        return bool(self.address & 0x80)


def encode_telegram(telegram: Telegram) -> bytes:
    """The bytes on the wire for ``telegram``: STX, ADR, LEN, CMD, DATA, [STATUS], CRC.

    :param telegram: a device frame (ADR & 0x80) with a STATUS byte, or a host frame without one.
    :raises CodecError: when it cannot be framed (STATUS missing or extra, payload over
        :data:`MAX_PAYLOAD`, a field that is not a byte).
    """
    status = telegram.status
    has_status = status is not None
    if has_status != telegram.from_device:
        raise CodecError('a device frame (ADR & 0x80) needs a STATUS byte; a host frame has none')
    length = 1 + len(telegram.data) + (1 if has_status else 0)
    if length > MAX_PAYLOAD:
        raise CodecError(f'payload of {length} bytes exceeds {MAX_PAYLOAD}')
    fields = (telegram.address, telegram.command) + ((status,) if status is not None else ())
    if any(not 0 <= value <= 0xFF for value in fields):
        raise CodecError('address, command and status must be bytes')
    body = bytearray((STX, telegram.address, length & 0xFF, length >> 8, telegram.command))
    body += telegram.data
    if status is not None:
        body.append(status)
    crc = sick_crc16(body)
    body += bytes((crc & 0xFF, crc >> 8))
    return bytes(body)


def decode_telegram(frame: bytes | bytearray | memoryview) -> Telegram:
    """Parse one whole frame (no leading ACK).

    :param frame: exactly one frame, STX to the CRC's high byte.
    :raises CodecError: on a framing or CRC error.
    """
    frame = bytes(frame)
    if len(frame) < 7:
        raise CodecError(f'frame of {len(frame)} bytes is too short')
    if frame[0] != STX:
        raise CodecError(f'frame starts with 0x{frame[0]:02x}, not STX')
    length = frame[2] | frame[3] << 8
    from_device = bool(frame[1] & 0x80)
    if not (2 if from_device else 1) <= length <= MAX_PAYLOAD:
        raise CodecError(f'LEN {length} out of range')
    if len(frame) != length + 6:
        raise CodecError(f'LEN {length} needs {length + 6} bytes, got {len(frame)}')
    crc = frame[-2] | frame[-1] << 8
    if crc != sick_crc16(frame[:-2]):
        raise CodecError(f'bad CRC 0x{crc:04x}')
    payload = frame[4:-2]
    if from_device:
        return Telegram(frame[1], payload[0], payload[1:-1], payload[-1])
    return Telegram(frame[1], payload[0], payload[1:])


class Deframer:
    """Splits a byte stream into telegrams sent by ``address`` (0x80: the device, 0x00: the host).

    Resynchronises on ``STX ADR``; a lone ACK/NAK byte between frames is counted, not skipped;
    any other byte outside a good frame (garbage, a frame with a bad CRC or a LEN out of range) is
    counted in :attr:`bytes_skipped`.  A bad CRC drops only the STX, and a complete valid frame
    found after an incomplete candidate wins over it, so a false ``02 80`` in garbage never
    swallows or delays the real frames after it.  :attr:`bad_crc` counts candidates whose CRC
    failed, which includes such false starts when their claimed length was complete.
    """

    def __init__(self, address: int = DEVICE_ADDRESS) -> None:
        """Start with an empty buffer and zero counters.

        :param address: the ADR of the frames to find: :data:`DEVICE_ADDRESS` (0x80) for a driver,
            :data:`HOST_ADDRESS` (0x00) for an emulator.
        """
        self.address = address
        self._header = bytes((STX, address))
        self._min_length = 2 if address & 0x80 else 1
        self._buffer = bytearray()
        self.telegrams = 0
        self.bad_crc = 0
        self.bytes_skipped = 0
        self.acks = 0
        self.naks = 0

    def reset(self) -> None:
        """Forget partial input (after a baud change, for instance)."""
        self._drop(len(self._buffer))

    @property
    def pending(self) -> int:
        """Bytes held waiting for the rest of a frame."""
        return len(self._buffer)

    def _drop(self, count: int) -> None:
        skipped = self._buffer[:count]
        self.acks += skipped.count(ACK)
        self.naks += skipped.count(NAK)
        self.bytes_skipped += count - skipped.count(ACK) - skipped.count(NAK)
        del self._buffer[:count]

    def _later_frame(self) -> int | None:
        """Where a complete, valid frame starts after the (incomplete) one at 0, if anywhere."""
        buffer = self._buffer
        start = buffer.find(self._header, 1)
        while start > 0:
            if len(buffer) - start >= 4:
                length = buffer[start + 2] | buffer[start + 3] << 8
                end = start + length + 6
                if self._min_length <= length <= MAX_PAYLOAD and end <= len(buffer):
                    try:
                        decode_telegram(buffer[start:end])
                    except CodecError:
                        pass
                    else:
                        return start
            start = buffer.find(self._header, start + 1)
        return None

    def feed(self, data: bytes | bytearray) -> list[Telegram]:
        """Add ``data``; return every telegram completed by it, in order.

        :param data: bytes as they came off the line, in any pieces.
        :returns: the whole valid telegrams, possibly none; the rest waits in the buffer or is counted.
        """
        self._buffer += data
        found: list[Telegram] = []
        buffer = self._buffer
        while True:
            start = buffer.find(self._header)
            if start < 0:
                # Keep a trailing STX: it may be the first half of the next header.
                keep = 1 if buffer[-1:] == b'\x02' else 0
                self._drop(len(buffer) - keep)
                return found
            if start:
                self._drop(start)
            if len(buffer) < 4:
                return found
            length = buffer[2] | buffer[3] << 8
            if not self._min_length <= length <= MAX_PAYLOAD:
                self._drop(1)
                continue
            if len(buffer) < length + 6:
                later = self._later_frame()
                if later is None:
                    return found
                self._drop(later)       # a false start in garbage: a whole frame follows it
                continue
            try:
                telegram = decode_telegram(buffer[:length + 6])
            except CodecError:
                self.bad_crc += 1
                self._drop(1)
                continue
            del buffer[:length + 6]
            self.telegrams += 1
            found.append(telegram)


# -- requests (host → device) ------------------------------------------------------------------
def request(command: int, data: bytes = b'') -> bytes:
    """A host frame (ADR 0x00) for ``command`` + ``data``.

    :param command: the request code (``CMD_*``).
    :param data: the request's data bytes after the command.
    :raises CodecError: when the frame would exceed :data:`MAX_PAYLOAD`.
    """
    return encode_telegram(Telegram(HOST_ADDRESS, command, bytes(data)))


def install_mode_request(kind: str = 'LMS') -> bytes:
    """``20 00 "SICK_LMS"`` (or ``"SICK_PLS"``): installation mode, needed to write the config.

    :param kind: ``'LMS'`` or ``'PLS'``: which password to send.
    :raises CodecError: an unknown kind.
    """
    if kind not in PASSWORDS:
        raise CodecError(f'unknown SICK type {kind!r}; expected LMS or PLS')
    return request(CMD_MODE, bytes((MODE_INSTALL,)) + PASSWORDS[kind])


def start_continuous_request() -> bytes:
    return request(CMD_MODE, bytes((MODE_CONTINUOUS,)))


def stop_continuous_request() -> bytes:
    return request(CMD_MODE, bytes((MODE_ON_REQUEST,)))


def baud_request(baudrate: int) -> bytes:
    """``20 40/41/42/48``: the device answers at the old rate, then switches.

    :param baudrate: 9600, 19200, 38400 or 500000.
    :raises CodecError: any other rate.
    """
    if baudrate not in BAUD_CODES:
        raise CodecError(f'baud rate {baudrate} not one of {sorted(BAUD_CODES)}')
    return request(CMD_MODE, bytes((BAUD_CODES[baudrate],)))


def status_request() -> bytes:
    return request(CMD_STATUS)


def type_request() -> bytes:
    return request(CMD_TYPE)


def reset_request() -> bytes:
    return request(CMD_RESET)


def one_scan_request() -> bytes:
    return request(CMD_SCAN, b'\x01')


def variant_request(angle: int, resolution: int) -> bytes:
    """``3B``: set the field of view and the angular resolution (LMS only).

    :param angle: field of view in degrees (100 or 180).
    :param resolution: angular resolution in 1/100 degree (25, 50 or 100).
    :raises CodecError: a value that does not fit 16 bits.
    """
    if not (0 <= angle <= 0xFFFF and 0 <= resolution <= 0xFFFF):
        raise CodecError('variant angle and resolution must fit 16 bits')
    return request(CMD_VARIANT, angle.to_bytes(2, 'little') + resolution.to_bytes(2, 'little'))


def read_config_request() -> bytes:
    return request(CMD_READ_CONFIG)


def write_config_request(config: SickConfig) -> bytes:
    """``77``: write a config block (installation mode must be on).

    :param config: the whole 34-byte block to write.
    """
    return request(CMD_WRITE_CONFIG, config.encode())


# -- replies (device → host) -------------------------------------------------------------------
def reply(command: int, data: bytes = b'', status: int = 0x10) -> bytes:
    """A device frame (ADR 0x80) with STATUS byte, as the emulator sends it.

    :param command: the reply code (request + 0x80, ``REPLY_*``).
    :param data: the reply's data between the command and the STATUS byte.
    :param status: the STATUS byte (0x10: no error).
    """
    return encode_telegram(Telegram(DEVICE_ADDRESS, command, bytes(data), status))


def decode_mode_reply(data: bytes) -> bool:
    """``A0 r``: whether the mode change was accepted.

    :param data: the A0 reply's data (without command and STATUS).
    :returns: True when r == 0.
    :raises CodecError: data without the result byte.
    """
    if len(data) < 1:
        raise CodecError('A0 reply without its result byte')
    return data[0] == 0


@dataclasses.dataclass(frozen=True)
class ScanValues:
    """A decoded B0 reply: 13-bit ``values``, 3-bit ``flags`` (field A/B/C-dazzle), ``units``."""

    values: tuple[int, ...]
    units: str = 'cm'
    flags: tuple[int, ...] = ()
    partial_index: int = 0

    @property
    def count(self) -> int:
        return len(self.values)


def decode_b0(data: bytes) -> ScanValues:
    """B0 data: count word (bits 0-9 count, 11-12 partial, 14-15 units), LE16 values.

    :param data: the B0 reply's data (without command and STATUS).
    :returns: the 13-bit values, their 3-bit flags, the units and the partial-scan index.
    :raises CodecError: data shorter than its count word announces.
    """
    if len(data) < 2:
        raise CodecError('B0 reply without its count word')
    word = data[0] | data[1] << 8
    count = word & 0x03FF
    units = {0: 'cm', 1: 'mm', 2: '10cm', 3: '10cm'}[word >> 14]
    if len(data) < 2 + 2 * count:
        raise CodecError(f'B0 reply announces {count} values but holds {(len(data) - 2) // 2}')
    raw = struct.unpack_from(f'<{count}H', data, 2)
    return ScanValues(tuple(v & RANGE_MASK for v in raw), units, tuple(v >> 13 for v in raw),
                      (word >> 11) & 0x3)


def encode_b0(values: Sequence[int], units: str = 'cm', flags: Sequence[int] = ()) -> bytes:
    """B0 data (without the command and STATUS) for ``values``.

    :param values: raw range values, each 0..8191 (8183 and above are error codes).
    :param units: ``'cm'``, ``'mm'`` or ``'10cm'``, coded in the count word.
    :param flags: one 3-bit flag per value (field A/B/C-dazzle); empty means all zero.
    :raises CodecError: unknown units, more than 1023 values, or a value or flag out of range.
    """
    if units not in _UNIT_BITS:
        raise CodecError(f'unknown units {units!r}')
    if len(values) > 0x3FF:
        raise CodecError(f'{len(values)} values do not fit the 10-bit count')
    flags = tuple(flags) or (0,) * len(values)
    if len(flags) != len(values):
        raise CodecError(f'{len(flags)} flags for {len(values)} values')
    if any(not 0 <= value <= RANGE_MASK for value in values) or any(not 0 <= f <= 7 for f in flags):
        raise CodecError('a value is outside 0..8191 or a flag outside 0..7')
    words = [value | flag << 13 for value, flag in zip(values, flags)]
    return struct.pack(f'<H{len(words)}H', _UNIT_BITS[units] << 14 | len(words), *words)


def value_meaning(value: int) -> str | None:
    """The documented meaning of an error code.

    :param value: a raw value (flag bits are masked off).
    :returns: the meaning of 8183..8191, or None for a range.
    """
    return ERROR_CODES.get(value & RANGE_MASK)


def value_to_metres(value: int, units: str) -> float:
    """A raw value in metres.

    :param value: a raw value (flag bits are masked off).
    :param units: the scan's units, ``'cm'``, ``'mm'`` or ``'10cm'``.
    :returns: metres; ``math.inf`` for 8183 (value > maximum), ``math.nan`` for the other error codes.
    :raises CodecError: unknown units.
    """
    value &= RANGE_MASK
    if value == VALUE_TOO_FAR:
        return math.inf
    if value in ERROR_CODES:
        return math.nan
    try:
        return value * UNIT_SCALE[units]
    except KeyError as error:
        raise CodecError(f'unknown units {units!r}') from error


@dataclasses.dataclass(frozen=True)
class VariantReply:
    """``BB ok angle resolution``: accepted, field of view (degrees), resolution (1/100 degree)."""

    ok: bool
    angle: int
    resolution: int

    def encode(self) -> bytes:
        return (bytes((1 if self.ok else 0,)) + self.angle.to_bytes(2, 'little')
                + self.resolution.to_bytes(2, 'little'))


def decode_bb(data: bytes) -> VariantReply:
    """``BB ok angle resolution``: the answer to a variant request.

    :param data: the BB reply's data (without command and STATUS).
    :raises CodecError: fewer than 5 data bytes.
    """
    if len(data) < 5:
        raise CodecError(f'BB reply of {len(data)} data bytes; 5 expected')
    return VariantReply(data[0] == 1, data[1] | data[2] << 8, data[3] | data[4] << 8)


CONFIG_SIZE = 34


@dataclasses.dataclass(frozen=True)
class SickConfig:
    """The 34-byte config block (``_parseSickConfigProfile``); bytes 7..33 kept as ``rest``."""

    blanking: int = 0
    stop_threshold: int = 0
    peak_threshold: int = 0
    availability: int = 0
    measuring_mode: int = 0
    units_code: int = 0
    rest: bytes = bytes(CONFIG_SIZE - 7)

    @property
    def units(self) -> str:
        """'cm', 'mm' or '10cm' from byte [6]."""
        return _CONFIG_UNITS.get(self.units_code, 'cm')

    def with_units(self, units: str) -> SickConfig:
        """This block with its units byte set.

        :param units: ``'cm'``, ``'mm'`` or ``'10cm'``.
        :raises CodecError: unknown units.
        """
        codes = {name: code for code, name in _CONFIG_UNITS.items()}
        if units not in codes:
            raise CodecError(f'unknown units {units!r}')
        return dataclasses.replace(self, units_code=codes[units])

    def encode(self) -> bytes:
        return (self.blanking.to_bytes(2, 'little')
                + bytes((self.stop_threshold, self.peak_threshold, self.availability,
                         self.measuring_mode, self.units_code)) + bytes(self.rest))

    @classmethod
    def decode(cls, data: bytes) -> SickConfig:
        """The block in ``data``.

        :param data: at least :data:`CONFIG_SIZE` bytes; more are ignored.
        :raises CodecError: a shorter block.
        """
        if len(data) < CONFIG_SIZE:
            raise CodecError(f'config block of {len(data)} bytes; {CONFIG_SIZE} expected')
        return cls(data[0] | data[1] << 8, data[2], data[3], data[4], data[5], data[6],
                   bytes(data[7:CONFIG_SIZE]))

    def patched(self, data: bytes) -> SickConfig:
        """This block with the first ``len(data)`` bytes replaced (a short ``77`` write, 1.5).

        :param data: the bytes written, from byte 0 (at most :data:`CONFIG_SIZE` are used).
        """
        merged = bytes(data[:CONFIG_SIZE]) + self.encode()[len(data):]
        return SickConfig.decode(merged)


def decode_f4(data: bytes) -> SickConfig:
    """``F4``: the config block read by a ``74`` request.

    :param data: the F4 reply's data (without command and STATUS).
    :raises CodecError: a block shorter than :data:`CONFIG_SIZE`.
    """
    return SickConfig.decode(data)


def decode_f7(data: bytes) -> tuple[bool, SickConfig]:
    """``F7 ok config``: (accepted, the config now in force).

    :param data: the F7 reply's data (without command and STATUS).
    :raises CodecError: fewer than 1 + :data:`CONFIG_SIZE` bytes.
    """
    if len(data) < 1 + CONFIG_SIZE:
        raise CodecError(f'F7 reply of {len(data)} data bytes; {1 + CONFIG_SIZE} expected')
    return data[0] == 1, SickConfig.decode(data[1:])


@dataclasses.dataclass(frozen=True)
class SickStatus:
    """The B1 fields drivers read; offsets count the command byte as 0 (docs/protocols.md 1.5)."""

    operating_mode: int = MODE_ON_REQUEST
    error: int = 0
    variant: int = 0
    motor_revolutions: int = 0
    measuring_mode: int = 0
    scan_angle: int = 180
    resolution: int = 100
    address: int = 0
    units_code: int = 0

    _BYTES: ClassVar[dict[str, int]] = {'operating_mode': 8, 'error': 9, 'variant': 18,
                                        'measuring_mode': 102, 'address': 120, 'units_code': 122}
    _WORDS: ClassVar[dict[str, int]] = {'motor_revolutions': 67, 'scan_angle': 107,
                                        'resolution': 109}

    def encode(self) -> bytes:
        data = bytearray(STATUS_SIZE)
        for name, offset in self._BYTES.items():
            data[offset - 1] = getattr(self, name)
        for name, offset in self._WORDS.items():
            data[offset - 1:offset + 1] = getattr(self, name).to_bytes(2, 'little')
        return bytes(data)

    @classmethod
    def decode(cls, data: bytes) -> SickStatus:
        """The fields of a B1 reply.

        :param data: the B1 reply's data (without command and STATUS), at least 122 bytes.
        :raises CodecError: a shorter reply.
        """
        if len(data) < 122:
            raise CodecError(f'B1 reply of {len(data)} data bytes; at least 122 expected')
        fields = {name: data[offset - 1] for name, offset in cls._BYTES.items()}
        fields.update({name: data[offset - 1] | data[offset] << 8
                       for name, offset in cls._WORDS.items()})
        return cls(**fields)


def decode_b1(data: bytes) -> SickStatus:
    """``B1``: the status fields drivers read (:class:`SickStatus`).

    :param data: the B1 reply's data (without command and STATUS), at least 122 bytes.
    :raises CodecError: a shorter reply.
    """
    return SickStatus.decode(data)


def decode_ba(data: bytes) -> str:
    """The type string of a BA reply, e.g. ``'LMS200;30106'``.

    :param data: the BA reply's data; trailing NULs are dropped.
    :raises CodecError: data that is not ASCII.
    """
    try:
        return bytes(data).rstrip(b'\x00').decode('ascii')
    except UnicodeDecodeError as error:
        raise CodecError('BA reply is not ASCII') from error


def interlace(resolution: int) -> int:
    """Mirror sweeps per full scan: 0.5° and 0.25° are interlaced over 2 and 4 sweeps (1.6).

    :param resolution: angular resolution in 1/100 degree; an unknown one counts as 1 sweep.
    """
    return {100: 1, 50: 2, 25: 4}.get(resolution, 1)


def value_count(angle: int, resolution: int) -> int:
    """Values in a scan (181, 361, 101...).

    :param angle: field of view in degrees.
    :param resolution: angular resolution in 1/100 degree.
    """
    return angle * 100 // resolution + 1


def telegram_size(count: int) -> int:
    """Bytes on the wire of a B0 telegram (372 for 181 values, 732 for 361).

    :param count: the number of values in the scan.
    """
    return 6 + 1 + 2 + 2 * count + 1

