"""NMEA codec fuzzers that reach the sentence bodies (issue 10, section 6).

- sentences with a correct checksum whose fields are drawn, one by one, from hand-annotated
  pools of good and bad field texts (NMEA 0183, docs/protocols.md 4): each decodes to exactly the
  values its fields stand for, or — when any field is bad — is refused;
- valid sentences with one character corrupted: never decoded (the XOR checksum catches it),
  except a checksum digit changed to its other case, which is the same number;
- a stream of valid sentences, other sentence types, corrupted sentences and junk lines, cut
  anywhere: exactly the valid GGA and RMC come out, in order — nothing lost, nothing spurious.
"""

from __future__ import annotations

import datetime
import math

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.gps.codec import GGA, KNOT, RMC, NmeaDeframer, checksum, decode

FUZZ = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
BAD = object()     # a field text the standard does not allow: the sentence must be refused

# -- field pools: (text on the wire, what it means) ----------------------------------------------
TIME = [('123519', 45319.0), ('123519.25', 45319.25), ('000000', 0.0), ('235960.5', 86400.5),
        ('', None), ('1235', BAD), ('246000', BAD), ('12a519', BAD), ('126019', BAD)]
LATITUDE = [(('4807.038', 'N'), 48 + 7.038 / 60), (('4807.038', 'S'), -(48 + 7.038 / 60)),
            (('4807', 'N'), 48 + 7 / 60), (('9000.000', 'S'), -90.0), (('', ''), None),
            (('4807.038', ''), BAD), (('', 'N'), BAD), (('48070.38', 'N'), BAD),
            (('4860.000', 'N'), BAD), (('9000.001', 'N'), BAD), (('4807.038', 'E'), BAD)]
LONGITUDE = [(('01131.000', 'E'), 11 + 31 / 60), (('01131.000', 'W'), -(11 + 31 / 60)),
             (('18000.000', 'W'), -180.0), (('', ''), None), (('1131.000', 'E'), BAD),
             (('18000.5', 'E'), BAD), (('01131.000', 'N'), BAD)]
QUALITY = [('0', 0), ('1', 1), ('2', 2), ('4', 4), ('6', 6), ('', 0), ('x', BAD), ('1234', BAD)]
SATELLITES = [('08', 8), ('12', 12), ('', 0), ('-1', BAD), ('1000', BAD)]
HDOP = [('0.9', 0.9), ('12', 12.0), ('', None), ('.9', BAD), ('-1', BAD), ('abc', BAD)]
ALTITUDE = [('545.4', 545.4), ('-12.5', -12.5), ('+5', 5.0), ('', None), ('1e3', BAD)]
UNIT = [('M', True), ('', True), ('F', BAD)]
GEOID = [('46.9', 46.9), ('-3.0', -3.0), ('', None), ('4.6.9', BAD)]
AGE = [('', None), ('2.5', 2.5), ('-1', BAD)]
STATION = [('', ''), ('0012', '0012')]
STATUS = [('A', 'A'), ('V', 'V'), ('X', BAD), ('', BAD)]
SPEED = [('022.4', 22.4 * KNOT), ('0', 0.0), ('', None), ('fast', BAD)]
COURSE = [('084.4', 84.4), ('', None), ('-1', BAD)]
DATE = [('230394', datetime.date(1994, 3, 23)), ('010100', datetime.date(2000, 1, 1)),
        ('', None), ('320194', BAD), ('2303', BAD), ('231394', BAD)]
VARIATION = [(('003.1', 'W'), -3.1), (('003.1', 'E'), 3.1), (('', ''), None),
             (('003.1', ''), BAD)]
MODE = [((), None), (('A',), 'A'), (('D',), 'D'), (('A', 'V'), 'A')]   # NMEA 2.3 / 4.1 tails


@st.composite
def entries(draw: st.DrawFn, *pools: list) -> list[tuple[object, object]]:
    """One entry of each pool: every one good, or (about half the time) one or two bad ones —
    so that both the decoding of good fields and the refusal of each bad one are reached."""
    bad = draw(st.one_of(st.just(set()), st.sets(st.integers(0, len(pools) - 1), min_size=1,
                                                  max_size=2)))
    chosen = []
    for index, pool in enumerate(pools):
        wanted = [entry for entry in pool if (entry[1] is BAD) == (index in bad)]
        chosen.append(draw(st.sampled_from(wanted or pool)))
    return chosen


def sentence(address: str, fields: list[str]) -> bytes:
    body = ','.join([address, *fields])
    return f'${body}*{checksum(body):02X}\r\n'.encode('ascii')


def close(got: object, want: object) -> bool:
    if isinstance(want, float) and isinstance(got, float):
        return math.isclose(got, want, rel_tol=1e-12, abs_tol=1e-9)
    return got == want


@FUZZ
@given(st.sampled_from(['GP', 'GN']), entries(TIME, LATITUDE, LONGITUDE, QUALITY, SATELLITES,
                                              HDOP, ALTITUDE, UNIT, GEOID, UNIT, AGE, STATION))
def test_gga_fields_decode_to_what_they_stand_for(talker: str, chosen: list) -> None:
    (time, lat, lon, quality, satellites, hdop, altitude, unit, geoid, geoid_unit, age,
     station) = chosen
    fields = [time[0], *lat[0], *lon[0], quality[0], satellites[0], hdop[0], altitude[0],
              unit[0], geoid[0], geoid_unit[0], age[0], station[0]]
    line = sentence(talker + 'GGA', fields)
    meanings = [time, lat, lon, quality, satellites, hdop, altitude, unit, geoid, geoid_unit,
                age, station]
    event('refused' if any(meaning is BAD for _, meaning in meanings) else 'decoded')
    if any(meaning is BAD for _, meaning in meanings):
        with pytest.raises(CodecError):
            decode(line)
        assert NmeaDeframer().feed(line) == []
        return
    gga = decode(line)
    assert isinstance(gga, GGA) and gga.talker == talker
    expected = {'time_of_day': time[1], 'latitude': lat[1], 'longitude': lon[1],
                'quality': quality[1], 'satellites': satellites[1], 'hdop': hdop[1],
                'altitude': altitude[1], 'geoid_separation': geoid[1], 'dgps_age': age[1],
                'dgps_station': station[1]}
    for name, want in expected.items():
        assert close(getattr(gga, name), want), (name, getattr(gga, name), want)
    assert NmeaDeframer().feed(line) == [gga]


@FUZZ
@given(st.sampled_from(['GP', 'GN']), entries(TIME, STATUS, LATITUDE, LONGITUDE, SPEED, COURSE,
                                              DATE, VARIATION, MODE))
def test_rmc_fields_decode_to_what_they_stand_for(talker: str, chosen: list) -> None:
    time, status, lat, lon, speed, course, date, variation, mode = chosen
    fields = [time[0], status[0], *lat[0], *lon[0], speed[0], course[0], date[0],
              *variation[0], *mode[0]]
    line = sentence(talker + 'RMC', fields)
    meanings = [time, status, lat, lon, speed, course, date, variation, mode]
    event('refused' if any(meaning is BAD for _, meaning in meanings) else 'decoded')
    if any(meaning is BAD for _, meaning in meanings):
        with pytest.raises(CodecError):
            decode(line)
        assert NmeaDeframer().feed(line) == []
        return
    rmc = decode(line)
    assert isinstance(rmc, RMC) and rmc.talker == talker
    expected = {'time_of_day': time[1], 'status': status[1], 'latitude': lat[1],
                'longitude': lon[1], 'speed': speed[1], 'course': course[1], 'date': date[1],
                'magnetic_variation': variation[1], 'mode': mode[1]}
    for name, want in expected.items():
        assert close(getattr(rmc, name), want), (name, getattr(rmc, name), want)
    assert NmeaDeframer().feed(line) == [rmc]


# -- valid sentences, corrupted ----------------------------------------------------------------
GOLDEN = [b'$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n',
          b'$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n']
valid_lines = st.one_of(st.sampled_from(GOLDEN), st.builds(
    lambda *f: sentence('GPGGA', list(f)), st.sampled_from(['123519', '000001.50']),
    st.sampled_from(['4807.038', '5920.988']), st.just('N'), st.sampled_from(['01131.000']),
    st.just('E'), st.sampled_from(['1', '2', '4']), st.sampled_from(['08', '12']),
    st.sampled_from(['0.9', '1.2']), st.sampled_from(['545.4', '30.0']), st.just('M'),
    st.just('46.9'), st.just('M'), st.just(''), st.just('')))
#: What a line's corruption may turn a character into: anything but the framing characters.
REPLACEMENTS = st.integers(0x20, 0x7E).filter(lambda c: c not in b'$*')


@FUZZ
@given(valid_lines, st.data())
def test_a_valid_sentence_with_one_character_corrupted_is_never_decoded(
        line: bytes, data: st.DataObject) -> None:
    index = data.draw(st.integers(1, len(line) - 3))          # between '$' and '\r\n'
    value = data.draw(REPLACEMENTS.filter(lambda c: c != line[index]))
    corrupted = line[:index] + bytes((value,)) + line[index + 1:]
    star = line.index(b'*')
    if index > star and corrupted.upper() == line.upper():
        assert decode(corrupted) == decode(line)                # 'a' and 'A' are one digit
        return
    with pytest.raises(CodecError):
        decode(corrupted)
    assert NmeaDeframer().feed(corrupted) == []


# -- streams: exactly the valid sentences -------------------------------------------------------
JUNK = st.binary(max_size=60).map(lambda b: b.replace(b'$', b'#').replace(b'\n', b' ') + b'\r\n')
#: Good sentences of types the reader does not decode: ignored, never returned.
OTHER = [sentence('GPGSV', '3,1,11,03,03,111,00,04,15,270,00,06,01,010,00,13,06,292,00'.split(',')),
         sentence('PGRME', ['15.0', 'M', '45.0', 'M', '25.0', 'M'])]


@st.composite
def corrupted_lines(draw: st.DrawFn) -> bytes:
    line = draw(valid_lines)
    index = draw(st.integers(1, line.index(b'*') - 1))        # a character of the body
    value = draw(REPLACEMENTS.filter(lambda c: c != line[index]))
    return line[:index] + bytes((value,)) + line[index + 1:]


@FUZZ
@given(st.lists(st.one_of(valid_lines.map(lambda b: ('sentence', b)),
                          corrupted_lines().map(lambda b: ('junk', b)),
                          st.sampled_from(OTHER).map(lambda b: ('other', b)),
                          JUNK.map(lambda b: ('junk', b))), max_size=10),
       st.lists(st.integers(1, 90), min_size=1, max_size=10))
def test_a_stream_gives_exactly_its_valid_sentences(items: list[tuple[str, bytes]],
                                                    cuts: list[int]) -> None:
    stream = b''.join(line for _, line in items)
    expected = [decode(line) for kind, line in items if kind == 'sentence']
    deframer = NmeaDeframer()
    got: list[GGA | RMC] = []
    position, index = 0, 0
    while position < len(stream):
        size = cuts[index % len(cuts)]
        got += deframer.feed(stream[position:position + size])
        position, index = position + size, index + 1
    assert got == expected
    assert deframer.sentences == len(expected)
    assert deframer.ignored == sum(kind == 'other' for kind, _ in items)
