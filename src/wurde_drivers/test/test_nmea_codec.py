"""The NMEA 0183 codec: the golden sentences of docs/protocols.md 4, framing rules, fuzzing."""

from __future__ import annotations

import datetime
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.gps.codec import (GGA, KNOT, RMC, ChecksumError, MissingChecksumError,
                                       NmeaDeframer, RawSentence, checksum, decode, encode,
                                       parse_frame)

# docs/protocols.md 4, verbatim.
GOLDEN_GGA = b'$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47'
GOLDEN_RMC = b'$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A'


# -- golden -----------------------------------------------------------------------------------
def test_golden_checksums() -> None:
    assert checksum(GOLDEN_GGA[1:-3]) == 0x47
    assert checksum(GOLDEN_RMC[1:-3]) == 0x6A
    assert checksum('GPGGA') == checksum(b'GPGGA')


def test_golden_gga_decodes() -> None:
    gga = decode(GOLDEN_GGA + b'\r\n')
    assert isinstance(gga, GGA)
    assert gga.time_of_day == 12 * 3600 + 35 * 60 + 19
    assert gga.latitude == pytest.approx(48 + 7.038 / 60)
    assert gga.longitude == pytest.approx(11 + 31.0 / 60)
    assert (gga.quality, gga.satellites) == (1, 8)
    assert gga.hdop == pytest.approx(0.9)
    assert gga.altitude == pytest.approx(545.4)
    assert gga.geoid_separation == pytest.approx(46.9)
    assert gga.dgps_age is None and gga.dgps_station == '' and gga.talker == 'GP'


def test_golden_rmc_decodes() -> None:
    rmc = decode(GOLDEN_RMC)
    assert isinstance(rmc, RMC)
    assert rmc.time_of_day == 45319.0 and rmc.status == 'A'
    assert rmc.latitude == pytest.approx(48.1173) and rmc.longitude == pytest.approx(11.5166667)
    assert rmc.speed == pytest.approx(22.4 * 0.514444, rel=1e-5)       # knots to m/s
    assert rmc.course == pytest.approx(84.4)
    assert rmc.date == datetime.date(1994, 3, 23)
    assert rmc.magnetic_variation == pytest.approx(-3.1)                # 3.1 W
    assert rmc.mode is None


def test_golden_sentences_survive_encode() -> None:
    for line in (GOLDEN_GGA, GOLDEN_RMC):
        sentence = decode(line)
        assert decode(encode(sentence)) == sentence
        assert encode(sentence).endswith(b'\r\n')


# -- framing rules --------------------------------------------------------------------------------
def test_a_wrong_checksum_is_refused() -> None:
    with pytest.raises(ChecksumError):
        decode(GOLDEN_GGA[:-2] + b'48')


def test_a_sentence_without_checksum_is_refused_as_player_does() -> None:
    with pytest.raises(MissingChecksumError):
        decode(GOLDEN_GGA[:-3])


def test_lower_case_hex_and_other_talkers_are_accepted() -> None:
    body = GOLDEN_GGA[1:-3].replace(b'GPGGA', b'GNGGA')
    gga = decode(b'$' + body + f'*{checksum(body):02x}'.encode())
    assert isinstance(gga, GGA) and gga.talker == 'GN'


def test_other_sentence_types_are_raw() -> None:
    body = b'GPGSV,3,1,11,03,03,111,00,04,15,270,00,06,01,010,00,13,06,292,00'
    raw = decode(b'$' + body + f'*{checksum(body):02X}'.encode())
    assert raw == RawSentence('GP', 'GSV', tuple(body.decode().split(',')[1:]))
    assert parse_frame(encode(raw)) == raw
    proprietary = decode(b'$PGRME,15.0,M,45.0,M,25.0,M*1C')
    assert isinstance(proprietary, RawSentence) and proprietary.talker == 'P'


def test_nmea_41_rmc_with_navigational_status_still_decodes() -> None:
    # The pynmea2 gotcha (docs/protocols.md 4): mode and navigational status after the variation.
    body = b'GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W,A,V'
    rmc = decode(b'$' + body + f'*{checksum(body):02X}'.encode())
    assert isinstance(rmc, RMC) and rmc.status == 'A' and rmc.mode == 'A'


def test_no_fix_gga_has_no_position() -> None:
    body = b'GPGGA,000001.00,,,,,0,00,,,M,,M,,'
    gga = decode(b'$' + body + f'*{checksum(body):02X}'.encode())
    assert isinstance(gga, GGA)
    assert gga.latitude is None and gga.longitude is None and gga.quality == 0
    assert gga.altitude is None and gga.hdop is None


@pytest.mark.parametrize('body', [
    b'GPGGA,123519,4807.038,X,01131.000,E,1,08,0.9,545.4,M,46.9,M,,',     # hemisphere
    b'GPGGA,123519,4867.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,',     # 67 minutes
    b'GPGGA,123519,9107.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,',     # 91 degrees
    b'GPGGA,253519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,',     # hour 25
    b'GPGGA,123519,4807.038,N,01131.000,E,1,08,nan,545.4,M,46.9,M,,',     # not a number
    b'GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M',       # field missing
    b'GPRMC,123519,X,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W',  # status
    b'GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,310294,003.1,W',  # 31 February
    b'gpgga,123519',                                                       # address
])
def test_bad_fields_are_codec_errors(body: bytes) -> None:
    with pytest.raises(CodecError):
        decode(b'$' + body + f'*{checksum(body):02X}'.encode())


def test_encoding_refuses_what_it_cannot_write() -> None:
    good = decode(GOLDEN_GGA)
    assert isinstance(good, GGA)
    for bad in (dict(latitude=91.0), dict(hdop=math.nan), dict(talker='gp'), dict(quality=12),
                dict(time_of_day=86400.0), dict(dgps_station='a,b')):
        with pytest.raises(CodecError):
            encode(GGA(**{**good.__dict__, **bad}))


# -- deframer -----------------------------------------------------------------------------------
def test_deframer_splits_on_newline_and_counts_trouble() -> None:
    deframer = NmeaDeframer()
    gsv = b'$GPGSV,1,1,00*79'
    stream = (b'junk before$' + GOLDEN_GGA[1:] + b'\n'                       # garbage then $
              + GOLDEN_RMC[:-2] + b'00\r\n'                                   # bad checksum
              + GOLDEN_GGA[:-3] + b'\r\n'                                     # no checksum
              + b'$GPGGA,' + b'1' * 130 + b'*00\r\n'                          # too long
              + gsv + b'\r\n'                                                 # other type
              + b'random words\r\n'
              + GOLDEN_RMC + b'\r\n')
    sentences = deframer.feed(stream)
    assert [type(s) for s in sentences] == [GGA, RMC]
    assert (deframer.bad_checksum, deframer.no_checksum, deframer.too_long, deframer.ignored,
            deframer.malformed, deframer.sentences) == (1, 1, 1, 1, 1, 2)
    assert deframer.bytes_skipped >= len(b'junk before') + 130


def test_a_runaway_line_without_newline_is_dropped() -> None:
    deframer = NmeaDeframer()
    assert deframer.feed(b'x' * 1000) == []
    assert deframer.feed(b'still the same line' + GOLDEN_GGA + b'\r\n') == []
    assert deframer.feed(GOLDEN_GGA + b'\r\n') == [decode(GOLDEN_GGA)]
    assert deframer.too_long == 1


# -- fuzz -----------------------------------------------------------------------------------------
_TIME = st.one_of(st.none(), st.integers(0, 8639999).map(lambda c: c / 100))
_LAT = st.one_of(st.none(), st.floats(-90, 90, allow_nan=False))
_LON = st.one_of(st.none(), st.floats(-180, 180, allow_nan=False))
_TENTH = st.one_of(st.none(), st.integers(0, 999).map(lambda t: t / 10))
_GGAS = st.builds(GGA, _TIME, _LAT, _LON, st.integers(0, 9), st.integers(0, 99), _TENTH,
                  st.one_of(st.none(), st.integers(-9999, 99999).map(lambda t: t / 10)),
                  st.one_of(st.none(), st.integers(-999, 999).map(lambda t: t / 10)), _TENTH,
                  st.from_regex(r'[0-9]{0,4}', fullmatch=True), st.sampled_from(['GP', 'GN']))
_RMCS = st.builds(RMC, _TIME, st.sampled_from(['A', 'V']), _LAT, _LON,
                  st.one_of(st.none(), st.integers(0, 99999).map(lambda k: k / 1000 * KNOT)),
                  st.one_of(st.none(), st.integers(0, 3599).map(lambda t: t / 10)),
                  st.one_of(st.none(), st.dates(datetime.date(1980, 1, 1),
                                                datetime.date(2079, 12, 31))),
                  st.one_of(st.none(), st.integers(-1800, 1800).map(lambda t: t / 10)),
                  st.one_of(st.none(), st.sampled_from(['A', 'D', 'N'])))


def _close(a: object, b: object) -> bool:
    for field in a.__dataclass_fields__:  # type: ignore[attr-defined]
        x, y = getattr(a, field), getattr(b, field)
        if isinstance(x, float) and isinstance(y, float):
            if not math.isclose(x, y, abs_tol=1e-6):
                return False
        elif x != y and not (field in ('latitude', 'longitude') and x == 0.0 and y == -0.0):
            return False
    return True


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=150))
def test_fuzz_decode_returns_a_sentence_or_codec_error(data: bytes) -> None:
    try:
        sentence = decode(data)
    except CodecError:
        return
    assert isinstance(sentence, (GGA, RMC, RawSentence))


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=100))
def test_fuzz_decode_of_checksummed_garbage_is_a_sentence_or_codec_error(body: bytes) -> None:
    # Random bodies with a correct checksum get past the frame check into the field parsers.
    line = b'$GPGGA,' + body.replace(b'*', b'').replace(b'$', b'')
    line += f'*{checksum(line[1:]):02X}'.encode()
    try:
        sentence = decode(line)
    except CodecError:
        return
    assert isinstance(sentence, (GGA, RawSentence))


@settings(max_examples=300, deadline=None)
@given(st.one_of(_GGAS, _RMCS))
def test_fuzz_encode_then_decode_gives_the_sentence_back(sentence: GGA | RMC) -> None:
    line = encode(sentence)
    back = decode(line)
    assert type(back) is type(sentence) and _close(back, sentence)
    assert encode(back) == line                     # and encoding is stable


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.binary(max_size=60), st.lists(st.one_of(_GGAS, _RMCS), max_size=3)),
                max_size=5), st.data())
def test_fuzz_stream_recovers_every_sentence_after_garbage(parts: list, data: st.DataObject) -> None:
    stream = b''
    expected = []
    for garbage, sentences in parts:
        stream += garbage + b'\n'
        for sentence in sentences:
            stream += encode(sentence)
            expected.append(encode(sentence))
    deframer = NmeaDeframer()
    got = []
    position = 0
    while position < len(stream):
        size = data.draw(st.integers(1, 90))
        got.extend(encode(s) for s in deframer.feed(stream[position:position + size]))
        position += size
    remaining = iter(got)
    assert all(any(line == candidate for candidate in remaining) for line in expected)
