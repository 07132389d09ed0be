"""Codec of NMEA 0183 sentences from a GPS receiver: GGA and RMC (docs/protocols.md 4).

A sentence is ``$<talker><type>,f1,...,fn*HH\\r\\n``; the checksum ``HH`` is the XOR of every
character between ``$`` and ``*``. As Player's ``garminnmea`` does, sentences without a checksum
are refused, lines are split on ``\\n`` and lines longer than 128 characters are dropped.
Written here rather than taken from pynmea2 (docs/protocols.md 4: low maintenance, and the XOR is
trivial).

Units: time of day in s since midnight UTC, latitude/longitude in signed decimal degrees (north,
east positive), altitude in m, speed in m/s (knots x 1852/3600), course in degrees true.
Pure functions over bytes; raises only :class:`~wurde_drivers.errors.CodecError` (or its
subclasses here) on bad input.
"""

from __future__ import annotations

import dataclasses
import datetime
import re

from ..errors import CodecError

__all__ = ['GGA', 'RMC', 'ChecksumError', 'MAX_LINE', 'MissingChecksumError', 'NmeaDeframer',
           'RawSentence', 'Sentence', 'checksum', 'decode', 'encode', 'parse_frame']

#: Longest line accepted (Player's limit; the standard's is 82).
MAX_LINE = 128
KNOT = 1852.0 / 3600.0

_FRAME = re.compile(rb'\$([^*$]*)\*([0-9A-Fa-f]{2})')
_ADDRESS = re.compile(r'[A-Z][A-Z0-9]{4}|P[A-Z0-9]{1,8}')
_DECIMAL = re.compile(r'[0-9]+(?:\.[0-9]*)?')
_SIGNED = re.compile(r'[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)')
_TIME = re.compile(r'([0-9]{2})([0-9]{2})([0-9]{2}(?:\.[0-9]+)?)')
_DATE = re.compile(r'([0-9]{2})([0-9]{2})([0-9]{2})')


class ChecksumError(CodecError):
    """The checksum does not match the sentence."""


class MissingChecksumError(CodecError):
    """A sentence without ``*HH``: refused, as Player refuses it."""


@dataclasses.dataclass(frozen=True)
class GGA:
    """Fix data. Fields absent from the sentence are None (no fix: no position)."""

    time_of_day: float | None
    latitude: float | None
    longitude: float | None
    quality: int
    satellites: int
    hdop: float | None
    altitude: float | None
    geoid_separation: float | None = None
    dgps_age: float | None = None
    dgps_station: str = ''
    talker: str = 'GP'


@dataclasses.dataclass(frozen=True)
class RMC:
    """Recommended minimum data. ``status`` 'A' valid, 'V' warning; ``magnetic_variation`` east
    positive; ``mode`` the NMEA 2.3 mode indicator if the sentence has one."""

    time_of_day: float | None
    status: str
    latitude: float | None
    longitude: float | None
    speed: float | None
    course: float | None
    date: datetime.date | None
    magnetic_variation: float | None = None
    mode: str | None = None
    talker: str = 'GP'


@dataclasses.dataclass(frozen=True)
class RawSentence:
    """Any other sentence with a good checksum: its talker, type and fields, undecoded."""

    talker: str
    kind: str
    fields: tuple[str, ...]


Sentence = GGA | RMC | RawSentence


# -- frame ------------------------------------------------------------------------------------
def checksum(body: bytes | str) -> int:
    """XOR of every character of ``body``.

    :param body: the text between ``$`` and ``*``.
    """
    data = body.encode('ascii') if isinstance(body, str) else body
    value = 0
    for byte in data:
        value ^= byte
    return value


def parse_frame(line: bytes) -> RawSentence:
    """Check the frame and checksum of one line and split its fields.

    :param line: one sentence from ``$``; a trailing line end is optional.
    :raises MissingChecksumError: no ``*HH``.
    :raises ChecksumError: the checksum does not match.
    :raises CodecError: anything else that is not a sentence.
    """
    line = line.rstrip(b'\r\n')
    if len(line) > MAX_LINE:
        raise CodecError(f'NMEA line longer than {MAX_LINE} characters')
    if not line.startswith(b'$') or b'$' in line[1:]:
        raise CodecError(f'not an NMEA sentence: {line[:40]!r}')
    match = _FRAME.fullmatch(line)
    if match is None:
        if b'*' not in line:
            raise MissingChecksumError(f'NMEA sentence without checksum: {line[:40]!r}')
        raise CodecError(f'bad NMEA frame: {line[:40]!r}')
    body = match.group(1)
    if any(byte < 0x20 or byte > 0x7E for byte in body):
        raise CodecError(f'NMEA sentence with non-printable characters: {line[:40]!r}')
    if checksum(body) != int(match.group(2), 16):
        raise ChecksumError(f'NMEA checksum {match.group(2).decode()} does not match '
                            f'{checksum(body):02X}: {line[:40]!r}')
    fields = body.decode('ascii').split(',')
    address = fields[0]
    if not _ADDRESS.fullmatch(address):
        raise CodecError(f'bad NMEA address {address!r}')
    if address.startswith('P'):
        return RawSentence('P', address[1:], tuple(fields[1:]))
    return RawSentence(address[:2], address[2:], tuple(fields[1:]))


def _frame(address: str, fields: list[str]) -> bytes:
    body = ','.join([address, *fields])
    if not body.isascii() or not body.isprintable() or '$' in body or '*' in body:
        raise CodecError(f'NMEA fields must be printable ASCII without $ and *: {body[:40]!r}')
    return f'${body}*{checksum(body):02X}\r\n'.encode('ascii')


# -- fields -----------------------------------------------------------------------------------
def _float(text: str, what: str, signed: bool = False) -> float | None:
    if not text:
        return None
    if not (_SIGNED if signed else _DECIMAL).fullmatch(text):
        raise CodecError(f'NMEA {what} is not a number: {text!r}')
    return float(text)


def _int(text: str, what: str) -> int:
    if not text:
        return 0
    if not text.isdigit() or not text.isascii() or len(text) > 3:
        raise CodecError(f'NMEA {what} is not a small integer: {text!r}')
    return int(text)


def _time(text: str) -> float | None:
    if not text:
        return None
    match = _TIME.fullmatch(text)
    if match is None:
        raise CodecError(f'NMEA time is not hhmmss.ss: {text!r}')
    hours, minutes, seconds = int(match.group(1)), int(match.group(2)), float(match.group(3))
    if hours > 23 or minutes > 59 or seconds >= 61.0:      # 60.x: a leap second
        raise CodecError(f'NMEA time out of range: {text!r}')
    return hours * 3600.0 + minutes * 60.0 + seconds


def _angle(text: str, hemisphere: str, degree_digits: int, what: str) -> float | None:
    if not text and not hemisphere:
        return None
    positive, negative = ('N', 'S') if degree_digits == 2 else ('E', 'W')
    if hemisphere not in (positive, negative):
        raise CodecError(f'NMEA {what} hemisphere must be {positive} or {negative}: {hemisphere!r}')
    if not _DECIMAL.fullmatch(text) or text.find('.') not in (-1, degree_digits + 2) \
            or len(text.split('.')[0]) != degree_digits + 2:
        raise CodecError(f'NMEA {what} is not {"d" * degree_digits}mm.mmm: {text!r}')
    degrees, minutes = int(text[:degree_digits]), float(text[degree_digits:])
    value = degrees + minutes / 60.0
    if minutes >= 60.0 or value > 90.0 * (degree_digits - 1):
        raise CodecError(f'NMEA {what} out of range: {text!r}')
    return value if hemisphere == positive else -value


def _date(text: str) -> datetime.date | None:
    if not text:
        return None
    match = _DATE.fullmatch(text)
    if match is None:
        raise CodecError(f'NMEA date is not ddmmyy: {text!r}')
    day, month, year = (int(group) for group in match.groups())
    try:
        return datetime.date(2000 + year if year < 80 else 1900 + year, month, day)
    except ValueError as error:
        raise CodecError(f'NMEA date out of range: {text!r}') from error


def _format_time(value: float | None) -> str:
    if value is None:
        return ''
    hundredths = round(value * 100) % (24 * 360000)
    hours, rest = divmod(hundredths, 360000)
    minutes, rest = divmod(rest, 6000)
    return f'{hours:02d}{minutes:02d}{rest // 100:02d}.{rest % 100:02d}'


def _format_angle(value: float | None, degree_digits: int, decimals: int) -> tuple[str, str]:
    if value is None:
        return '', ''
    scale = 10 ** decimals
    total = round(abs(value) * 60 * scale)
    positive = value >= 0 or total == 0             # no "S" for a latitude written as 0
    hemisphere = ('N' if positive else 'S') if degree_digits == 2 else ('E' if positive else 'W')
    degrees, rest = divmod(total, 60 * scale)
    minutes, fraction = divmod(rest, scale)
    return f'{degrees:0{degree_digits}d}{minutes:02d}.{fraction:0{decimals}d}', hemisphere


def _number(value: float | None, decimals: int, low: float = 0.0,
            high: float = 1e6) -> str:
    if value is None:
        return ''
    if not low <= value <= high:           # also refuses NaN
        raise CodecError(f'NMEA field out of range [{low}, {high}]: {value}')
    return f'{value:.{decimals}f}'


# -- sentences --------------------------------------------------------------------------------
def _decode_gga(raw: RawSentence) -> GGA:
    f = raw.fields
    if len(f) != 14:
        raise CodecError(f'GGA needs 14 fields, got {len(f)}')
    if f[9] not in ('', 'M') or f[11] not in ('', 'M'):
        raise CodecError(f'GGA altitude units must be M: {f[9]!r} {f[11]!r}')
    return GGA(_time(f[0]), _angle(f[1], f[2], 2, 'latitude'), _angle(f[3], f[4], 3, 'longitude'),
               _int(f[5], 'quality'), _int(f[6], 'satellites'), _float(f[7], 'hdop'),
               _float(f[8], 'altitude', signed=True), _float(f[10], 'geoid separation', signed=True),
               _float(f[12], 'DGPS age'), f[13], raw.talker)


def _decode_rmc(raw: RawSentence) -> RMC:
    f = raw.fields
    if len(f) not in (11, 12, 13):
        raise CodecError(f'RMC needs 11 to 13 fields, got {len(f)}')
    if f[1] not in ('A', 'V'):
        raise CodecError(f'RMC status must be A or V: {f[1]!r}')
    variation = _float(f[9], 'magnetic variation')
    if variation is not None:
        if f[10] not in ('E', 'W'):
            raise CodecError(f'RMC magnetic variation needs E or W: {f[10]!r}')
        variation = variation if f[10] == 'E' else -variation
    knots = _float(f[6], 'speed')
    return RMC(_time(f[0]), f[1], _angle(f[2], f[3], 2, 'latitude'),
               _angle(f[4], f[5], 3, 'longitude'), None if knots is None else knots * KNOT,
               _float(f[7], 'course'), _date(f[8]), variation,
               f[11] if len(f) > 11 else None, raw.talker)


def decode(line: bytes) -> Sentence:
    """One sentence: :class:`GGA`, :class:`RMC`, or :class:`RawSentence` for other types.

    :param line: one sentence from ``$``; a trailing line end is optional.
    :raises CodecError: bad frame, checksum (:class:`ChecksumError`), missing checksum
        (:class:`MissingChecksumError`) or field.
    """
    raw = parse_frame(line)
    if raw.kind == 'GGA' and raw.talker != 'P':
        return _decode_gga(raw)
    if raw.kind == 'RMC' and raw.talker != 'P':
        return _decode_rmc(raw)
    return raw


def encode(sentence: Sentence, *, minute_decimals: int = 5) -> bytes:
    """The line for ``sentence``, with checksum and ``\\r\\n``.

    Times get two decimals; RMC gets the classic 11 fields plus the mode only if it has one.

    :param sentence: a GGA, an RMC or any other sentence's raw fields.
    :param minute_decimals: decimals of a minute for latitude and longitude (5: 1.9 cm).
    :raises CodecError: a field that cannot be written (bad talker, status, out-of-range value).
    """
    if isinstance(sentence, RawSentence):
        address = ('P' if sentence.talker == 'P' else sentence.talker) + sentence.kind
        if not _ADDRESS.fullmatch(address) or any(',' in field for field in sentence.fields):
            raise CodecError(f'cannot encode NMEA sentence {sentence!r}')
        return _frame(address, list(sentence.fields))
    if not re.fullmatch(r'[A-Z]{2}', sentence.talker):
        raise CodecError(f'NMEA talker must be two letters: {sentence.talker!r}')
    for value, limit in ((sentence.latitude, 90.0), (sentence.longitude, 180.0)):
        if value is not None and not abs(value) <= limit:
            raise CodecError(f'NMEA coordinate out of range: {value}')
    if sentence.time_of_day is not None and not 0.0 <= sentence.time_of_day < 86400.0:
        raise CodecError(f'NMEA time of day out of range: {sentence.time_of_day}')
    lat, ns = _format_angle(sentence.latitude, 2, minute_decimals)
    lon, ew = _format_angle(sentence.longitude, 3, minute_decimals)
    if isinstance(sentence, GGA):
        if not 0 <= sentence.quality <= 9 or not 0 <= sentence.satellites <= 99:
            raise CodecError(f'GGA quality or satellites out of range: {sentence}')
        if ',' in sentence.dgps_station:
            raise CodecError(f'GGA DGPS station id cannot be written: {sentence.dgps_station!r}')
        return _frame(sentence.talker + 'GGA', [
            _format_time(sentence.time_of_day), lat, ns, lon, ew, str(sentence.quality),
            f'{sentence.satellites:02d}', _number(sentence.hdop, 1, high=99.9),
            _number(sentence.altitude, 1, -1e5, 1e6), 'M',
            _number(sentence.geoid_separation, 1, -1e3, 1e3), 'M', _number(sentence.dgps_age, 1),
            sentence.dgps_station])
    if isinstance(sentence, RMC):
        if sentence.status not in ('A', 'V'):
            raise CodecError(f'RMC status must be A or V: {sentence.status!r}')
        variation = sentence.magnetic_variation
        fields = [
            _format_time(sentence.time_of_day), sentence.status, lat, ns, lon, ew,
            _number(None if sentence.speed is None else sentence.speed / KNOT, 3),
            _number(sentence.course, 1, high=360.0),
            '' if sentence.date is None else sentence.date.strftime('%d%m%y'),
            _number(None if variation is None else abs(variation), 1, high=180.0),
            '' if variation is None else ('E' if variation >= 0 else 'W')]
        if sentence.mode is not None:
            fields.append(sentence.mode)
        return _frame(sentence.talker + 'RMC', fields)
    raise CodecError(f'not an NMEA sentence: {sentence!r}')


# -- stream -----------------------------------------------------------------------------------
class NmeaDeframer:
    """GGA and RMC sentences out of a byte stream, with every kind of trouble counted.

    Lines are split on ``\\n``; a line's sentence starts at its last ``$`` (what comes before is
    counted in ``bytes_skipped``); a line longer than :data:`MAX_LINE` is dropped whole.

    Counters: ``sentences`` (GGA/RMC returned), ``ignored`` (other types), ``bad_checksum``,
    ``no_checksum``, ``too_long``, ``malformed``, ``bytes_skipped``.
    """

    def __init__(self) -> None:
        self._buffer = bytearray()
        self._discarding = False
        self.sentences = 0
        self.ignored = 0
        self.bad_checksum = 0
        self.no_checksum = 0
        self.too_long = 0
        self.malformed = 0
        self.bytes_skipped = 0

    def reset(self) -> None:
        """Forget a partial line."""
        self._buffer.clear()
        self._discarding = False

    def feed(self, data: bytes) -> list[GGA | RMC]:
        """Every GGA and RMC completed by ``data``, in order.

        :param data: bytes as read from the line; a partial line is kept, other sentence types and
            bad lines are only counted.
        """
        out: list[GGA | RMC] = []
        self._buffer += data
        while True:
            end = self._buffer.find(b'\n')
            if end < 0:
                if len(self._buffer) > MAX_LINE + 1:
                    if not self._discarding:
                        self.too_long += 1
                    self.bytes_skipped += len(self._buffer)
                    self._buffer.clear()
                    self._discarding = True
                return out
            line = bytes(self._buffer[:end + 1])
            del self._buffer[:end + 1]
            if self._discarding:
                self._discarding = False
                self.bytes_skipped += len(line)
                continue
            sentence = self._line(line.rstrip(b'\r\n'))
            if sentence is not None:
                out.append(sentence)

    def _line(self, line: bytes) -> GGA | RMC | None:
        if len(line) > MAX_LINE:
            self.too_long += 1
            self.bytes_skipped += len(line) + 1
            return None
        start = line.rfind(b'$')
        if start < 0:
            self.bytes_skipped += len(line) + 1
            if line.strip():
                self.malformed += 1
            return None
        self.bytes_skipped += start
        try:
            sentence = decode(line[start:])
        except ChecksumError:
            self.bad_checksum += 1
        except MissingChecksumError:
            self.no_checksum += 1
        except CodecError:
            self.malformed += 1
        else:
            if isinstance(sentence, RawSentence):
                self.ignored += 1
                return None
            self.sentences += 1
            return sentence
        self.bytes_skipped += len(line) - start + 1
        return None
