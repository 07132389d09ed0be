"""Crossbow DMU codec fuzzers that reach the packet bodies (issue 10, section 6).

- packets with a good header and checksum around random words: each word decodes to what the
  manual's conversions say (written out here, not taken from the codec), in both modes, with
  random unit ranges; the serial-number reply likewise;
- valid packets with one byte corrupted anywhere: never decoded (the sum catches a single byte);
- a stream of valid packets, corrupted packets and junk, cut anywhere: exactly the valid packets
  come out, in order — nothing lost, nothing spurious.  An 8-bit sum cannot rule out a false
  start (a 0xFF in garbage followed by bytes whose sum matches: 1 in 256, the deframer says so),
  so draws in which such a window exists are set aside; the rest must be exact.
"""

from __future__ import annotations

import math
import struct

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from wurde_drivers.dmu import codec as dmu
from wurde_drivers.dmu.codec import DmuDeframer, DmuMode, DmuScale
from wurde_drivers.errors import CodecError

FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
FULL = 2 ** 15 - 1
DEG = math.pi / 180


def framed(body: bytes) -> bytes:
    """Header 0xFF, ``body``, and the sum of the body mod 256 (the family's checksum)."""
    return b'\xff' + body + bytes((sum(body) & 0xFF,))


scales = st.builds(DmuScale, st.sampled_from([2.0, 4.0, 10.0]),
                   st.sampled_from([50.0, 100.0, 200.0]))


@FUZZ
@given(st.sampled_from(list(DmuMode)), st.lists(st.integers(0, 0xFFFF), min_size=10,
                                                 max_size=10), scales)
def test_random_words_decode_to_what_the_manual_says(mode: DmuMode, words: list[int],
                                                     scale: DmuScale) -> None:
    count = 10 if mode is DmuMode.ANGLE else 8
    words = words[:count]
    frame = framed(struct.pack(f'>{count}H', *words))
    packet = dmu.decode_packet(frame, mode, scale)
    assert DmuDeframer(mode, scale).feed(frame) == [packet]          # the same out of a stream
    signed = [w - 0x10000 if w & 0x8000 else w for w in words]
    if mode is DmuMode.ANGLE:
        assert packet.roll == pytest.approx(signed[0] * 180 / FULL * DEG)
        assert packet.pitch == pytest.approx(signed[1] * 180 / FULL * DEG)
        signed, words = signed[2:], words[2:]
    else:
        assert packet.roll is None and packet.pitch is None
    rate = scale.rate_range * 1.5 / FULL * DEG
    accel = scale.g_range * 1.5 / FULL * 9.80665
    assert (packet.rate_x, packet.rate_y, packet.rate_z) == pytest.approx(
        [w * rate for w in signed[0:3]])
    assert (packet.accel_x, packet.accel_y, packet.accel_z) == pytest.approx(
        [w * accel for w in signed[3:6]])
    assert packet.temperature == pytest.approx((words[6] * 5 / 4096 - 1.375) * 44.44)  # unsigned
    assert packet.time_ticks == words[7] and packet.mode is mode


@FUZZ
@given(st.integers(0, 0xFFFFFFFF))
def test_a_random_serial_number_decodes(number: int) -> None:
    assert dmu.decode_serial_number(framed(number.to_bytes(4, 'big'))) == number


@st.composite
def valid_packets(draw: st.DrawFn, mode: DmuMode) -> bytes:
    count = 10 if mode is DmuMode.ANGLE else 8
    return framed(struct.pack(f'>{count}H', *draw(st.lists(st.integers(0, 0xFFFF),
                                                           min_size=count, max_size=count))))


@st.composite
def corrupted(draw: st.DrawFn, packet: bytes) -> bytes:
    """``packet`` with one byte (anywhere) replaced."""
    index = draw(st.integers(0, len(packet) - 1))
    value = draw(st.integers(0, 255).filter(lambda v: v != packet[index]))
    return packet[:index] + bytes((value,)) + packet[index + 1:]


@FUZZ
@given(st.sampled_from(list(DmuMode)).flatmap(
    lambda mode: st.tuples(st.just(mode), valid_packets(mode).flatmap(corrupted))))
def test_a_valid_packet_with_one_byte_corrupted_is_never_decoded(
        pair: tuple[DmuMode, bytes]) -> None:
    mode, packet = pair
    with pytest.raises(CodecError):
        dmu.decode_packet(packet, mode)
    assert DmuDeframer(mode).feed(packet) == []


def _false_starts(stream: bytes, placed: set[int], length: int) -> bool:
    """Whether a 0xFF anywhere but at a real packet starts a window whose sum matches."""
    for start in range(len(stream) - length + 1):
        if stream[start] == 0xFF and start not in placed:
            window = stream[start:start + length]
            if sum(window[1:-1]) & 0xFF == window[-1]:
                return True
    return False


@FUZZ
@given(st.sampled_from(list(DmuMode)).flatmap(lambda mode: st.tuples(st.just(mode), st.lists(
    st.one_of(valid_packets(mode).map(lambda b: ('packet', b)),
              valid_packets(mode).flatmap(corrupted).map(lambda b: ('junk', b)),
              st.binary(max_size=30).map(lambda b: ('junk', b))), max_size=10))),
       st.lists(st.integers(1, 40), min_size=1, max_size=10))
def test_a_stream_gives_exactly_its_valid_packets(drawn: tuple[DmuMode, list[tuple[str, bytes]]],
                                                  cuts: list[int]) -> None:
    mode, items = drawn
    stream, placed = b'', set()
    for kind, data in items:
        if kind == 'packet':
            placed.add(len(stream))
        stream += data
    assume(not _false_starts(stream, placed, dmu.packet_length(mode)))
    deframer = DmuDeframer(mode)
    got = []
    position, index = 0, 0
    while position < len(stream):
        size = cuts[index % len(cuts)]
        got += deframer.feed(stream[position:position + size])
        position, index = position + size, index + 1
    assert got == [dmu.decode_packet(data, mode) for kind, data in items if kind == 'packet']
    assert deframer.packets == len(got)
