"""SICK LMS/PLS codec: the golden vectors of docs/protocols.md 1.3 and 1.6, then fuzzing."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.sick import codec as sick

# docs/protocols.md 1.3, the table verbatim: (request builder, bytes on the wire).
GOLDEN_REQUESTS = [
    (sick.start_continuous_request, '02 00 02 00 20 24 34 08'),
    (sick.stop_continuous_request, '02 00 02 00 20 25 35 08'),
    (lambda: sick.baud_request(38400), '02 00 02 00 20 40 50 08'),
    (lambda: sick.baud_request(19200), '02 00 02 00 20 41 51 08'),
    (lambda: sick.baud_request(9600), '02 00 02 00 20 42 52 08'),
    (lambda: sick.baud_request(500000), '02 00 02 00 20 48 58 08'),
    (sick.status_request, '02 00 01 00 31 15 12'),
    (sick.type_request, '02 00 01 00 3a 1e 12'),
    (sick.one_scan_request, '02 00 02 00 30 01 31 18'),
    (lambda: sick.variant_request(180, 50), '02 00 05 00 3b b4 00 32 00 3b 1f'),
    (lambda: sick.install_mode_request('LMS'), '02 00 0a 00 20 00 53 49 43 4b 5f 4c 4d 53 be c5'),
]
MODE_REPLY = '06 02 80 03 00 a0 00 10 16 0a'


@pytest.mark.parametrize(('build', 'wire'), GOLDEN_REQUESTS)
def test_golden_requests(build, wire: str) -> None:
    frame = bytes.fromhex(wire)
    assert build() == frame
    assert sick.sick_crc16(frame[:-2]) == frame[-2] | frame[-1] << 8
    telegram = sick.decode_telegram(frame)
    assert telegram.address == sick.HOST_ADDRESS and telegram.status is None
    assert sick.encode_telegram(telegram) == frame


def test_golden_mode_reply_with_leading_ack() -> None:
    wire = bytes.fromhex(MODE_REPLY)
    assert sick.reply(sick.REPLY_MODE, b'\x00', 0x10) == wire[1:]
    deframer = sick.Deframer()
    (telegram,) = deframer.feed(wire)
    assert telegram == sick.Telegram(0x80, 0xA0, b'\x00', 0x10)
    assert sick.decode_mode_reply(telegram.data) is True
    assert (deframer.acks, deframer.bytes_skipped, deframer.bad_crc) == (1, 0, 0)


@pytest.mark.parametrize(('count', 'units', 'header', 'size'), [
    (181, 'cm', '02 80 6e 01 b0 b5 00', 372),
    (361, 'cm', '02 80 d6 02 b0 69 01', 732),
    (361, 'mm', '02 80 d6 02 b0 69 41', 732),
])
def test_golden_b0_headers(count: int, units: str, header: str, size: int) -> None:
    frame = sick.reply(sick.REPLY_SCAN, sick.encode_b0([400] * count, units))
    assert frame.startswith(bytes.fromhex(header))
    assert len(frame) == size == sick.telegram_size(count)
    decoded = sick.decode_b0(sick.decode_telegram(frame).data)
    assert (decoded.count, decoded.units, decoded.values[0]) == (count, units, 400)


def test_b0_values_flags_and_error_codes() -> None:
    data = bytes.fromhex('0500') + bytes.fromhex('9001 f71f fe3f ff5f 0a80')
    decoded = sick.decode_b0(data)
    assert decoded.values == (400, 8183, 8190, 8191, 10)
    assert decoded.flags == (0, 0, 1, 2, 4)
    assert sick.value_meaning(8183) == 'value > maximum'
    assert sick.value_meaning(8190) == 'dazzling'
    assert sick.value_meaning(400) is None
    assert sick.value_to_metres(400, 'cm') == pytest.approx(4.0)
    assert sick.value_to_metres(400, 'mm') == pytest.approx(0.4)
    assert sick.value_to_metres(8183, 'cm') == math.inf
    assert all(math.isnan(sick.value_to_metres(v, 'cm')) for v in range(8184, 8192))


def test_replies_round_trip() -> None:
    variant = sick.VariantReply(True, 180, 50)
    assert sick.decode_bb(variant.encode()) == variant
    config = sick.SickConfig(availability=2, units_code=1)
    assert sick.decode_f4(config.encode()).units == 'mm'
    assert sick.decode_f7(b'\x01' + config.encode()) == (True, config)
    assert config.patched(bytes(7)).units == 'cm'
    status = sick.SickStatus(operating_mode=0x24, scan_angle=180, resolution=50, units_code=1)
    data = status.encode()
    assert len(data) + 1 >= 124 and data[107 - 1:111 - 1] == bytes.fromhex('b4003200')
    assert sick.decode_b1(data) == status
    assert sick.decode_ba(b'LMS200;30106') == 'LMS200;30106'


def test_bad_crc_and_truncated_frames() -> None:
    frame = bytes.fromhex('02 00 02 00 20 24 34 08')
    with pytest.raises(CodecError):
        sick.decode_telegram(frame[:-1] + b'\x09')
    for cut in range(len(frame)):
        with pytest.raises(CodecError):
            sick.decode_telegram(frame[:cut])
    deframer = sick.Deframer(sick.HOST_ADDRESS)
    assert deframer.feed(frame[:-1] + b'\x09' + frame[:5]) == []
    assert deframer.bad_crc == 1
    assert deframer.feed(frame[5:]) == [sick.decode_telegram(frame)]


def test_garbage_ack_nak_between_frames() -> None:
    frame = sick.reply(sick.REPLY_MODE, b'\x00')
    stream = b'\x55\xaa' + frame + b'\x15\x02\x80\x10\x00\xff' + frame + b'\x06'
    deframer = sick.Deframer()
    assert deframer.feed(stream) == [sick.decode_telegram(frame)] * 2
    assert (deframer.naks, deframer.acks) == (1, 1)
    assert deframer.bytes_skipped == 2 + 5


def test_bad_requests_are_codec_errors() -> None:
    for bad in (lambda: sick.baud_request(4800), lambda: sick.install_mode_request('LMX'),
                lambda: sick.encode_b0([9000]), lambda: sick.encode_b0([1] * 1024),
                lambda: sick.encode_telegram(sick.Telegram(0x80, 0xB0, b'')),
                lambda: sick.encode_telegram(sick.Telegram(0, 0x20, bytes(900)))):
        with pytest.raises(CodecError):
            bad()


# -- fuzz ----------------------------------------------------------------------------------------
DECODERS = [sick.decode_telegram, sick.decode_b0, sick.decode_bb, sick.decode_f4, sick.decode_f7,
            sick.decode_b1, sick.decode_ba, sick.decode_mode_reply]


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=900), st.sampled_from(DECODERS))
def test_fuzz_decoders_raise_only_codec_error(data: bytes, decoder) -> None:
    try:
        result = decoder(data)
    except CodecError:
        return
    assert result is not None and not isinstance(result, BaseException)


telegrams = st.one_of(
    st.builds(sick.Telegram, st.just(sick.HOST_ADDRESS), st.integers(0, 255),
              st.binary(max_size=60)),
    st.builds(sick.Telegram, st.just(sick.DEVICE_ADDRESS), st.integers(0, 255),
              st.binary(max_size=60), st.integers(0, 255)))


@settings(max_examples=300, deadline=None)
@given(telegrams)
def test_fuzz_encode_then_decode(telegram: sick.Telegram) -> None:
    assert sick.decode_telegram(sick.encode_telegram(telegram)) == telegram


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 8191), st.integers(0, 7)), max_size=401),
       st.sampled_from(['cm', 'mm', '10cm']))
def test_fuzz_b0_round_trip(pairs, units: str) -> None:
    values = [v for v, _ in pairs]
    flags = [f for _, f in pairs]
    decoded = sick.decode_b0(sick.encode_b0(values, units, flags) + b'\x10')
    assert decoded == sick.ScanValues(tuple(values), units, tuple(flags) if pairs else ())


@settings(max_examples=300, deadline=None)
@given(st.lists(st.one_of(st.binary(max_size=40).map(lambda b: ('junk', b)),
                          st.builds(sick.Telegram, st.just(0x80), st.integers(0, 255),
                                    st.binary(max_size=40), st.integers(0, 255))
                          .map(lambda t: ('frame', t))), max_size=12),
       st.lists(st.integers(1, 50), min_size=1, max_size=20))
def test_fuzz_stream_recovers_every_frame(pieces, cuts) -> None:
    stream = b''.join(sick.encode_telegram(p) if kind == 'frame' else p for kind, p in pieces)
    # Valid frames end the stream, so a false start in the last junk cannot hold one back.
    tail = sick.Telegram(0x80, 0xA0, b'\x00', 0x10)
    stream += sick.encode_telegram(tail)
    expected = [p for kind, p in pieces if kind == 'frame'] + [tail]
    deframer = sick.Deframer()
    got: list[sick.Telegram] = []
    position, index = 0, 0
    while position < len(stream):
        size = cuts[index % len(cuts)]
        got += deframer.feed(stream[position:position + size])
        position += size
        index += 1
    # Junk may by chance hold a valid frame of its own: every real one must be there, in order.
    iterator = iter(got)
    assert all(any(g == e for g in iterator) for e in expected)
