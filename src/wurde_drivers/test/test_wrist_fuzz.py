"""Wrist (PowerCube on CAN) codec fuzzers that reach the frame bodies (issue 10, section 6).

CAN frames come whole (the bus checks their CRC), so the codec's frames are the bodies: frames
on the wrist's ids with random data, valid frames with one data byte corrupted, and foreign
frames (other ids, 29-bit ids) all decode to exactly what the layouts in the codec's docstring
(PowerCube sources) say, written out here independently — or are refused.  No frame decodes
into something it does not hold: a stream of mixed frames gives exactly the expected replies.
"""

from __future__ import annotations

import math
import struct

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.wrist import codec
from wurde_drivers.wrist.codec import CanFrame, Command, Motion, Param, WristCommand, WristReply

FUZZ = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ACK, GET, PUT, ALL, OK = 0x0A0, 0x0C0, 0x0E0, 0x100, 0x64
SIMPLE = {0x00: Command.RESET, 0x01: Command.HOME, 0x02: Command.HALT}
PARAMS = {p.value: p for p in Param}


def value_of(param: int, raw: bytes) -> float | int | None:
    """A parameter's 4 value bytes: uint32 for CubeState, else a finite float32 (LE); None if
    not a finite float."""
    if param == Param.CUBE_STATE:
        return int.from_bytes(raw, 'little')
    value = struct.unpack('<f', raw)[0]
    return value if math.isfinite(value) else None


def expected_reply(frame: CanFrame) -> WristReply | None:
    """What a module -> host acknowledge holds (None: not one)."""
    if frame.is_extended or not 1 <= len(frame.data) <= 8:
        return None
    module, data = frame.arbitration_id - ACK, frame.data
    if not 1 <= module <= 31:
        return None
    if data[0] in SIMPLE:
        return WristReply(SIMPLE[data[0]], module) if data[1:] == bytes([OK]) else None
    if len(data) < 2:
        return None
    if data[0] == Command.GET_EXTENDED:
        if data[1] not in PARAMS or len(data) != 6:
            return None
        value = value_of(data[1], data[2:6])
        return None if value is None else WristReply(Command.GET_EXTENDED, module,
                                                     PARAMS[data[1]], value)
    if data[0] == Command.SET_EXTENDED:
        ok = len(data) == 3 and data[2] == OK and data[1] in PARAMS
        return WristReply(Command.SET_EXTENDED, module, PARAMS[data[1]]) if ok else None
    if data[0] != Command.SET_MOTION:
        return None
    if data[1] == Motion.FRAMP_MODE:
        ok = len(data) == 3 and data[2] == OK
        return WristReply(Command.SET_MOTION, module, Motion.FRAMP_MODE) if ok else None
    if data[1] != Motion.FRAMP_ACK or len(data) != 8:
        return None
    value = value_of(Param.ACT_POS, data[2:6])
    return None if value is None else WristReply(Command.SET_MOTION, module, Motion.FRAMP_ACK,
                                                 value, data[6], data[7])


def expected_command(frame: CanFrame) -> WristCommand | None:
    """What a host -> module command holds (None: not one)."""
    if frame.is_extended or not 1 <= len(frame.data) <= 8:
        return None
    ident, data = frame.arbitration_id, frame.data
    if ident == ALL:
        return WristCommand(SIMPLE[data[0]], 0) if data[0] in SIMPLE and len(data) == 1 else None
    base, module = ident & ~0x1F, ident & 0x1F
    if base not in (PUT, GET) or module == 0:
        return None
    if base == GET:
        ok = data[0] == Command.GET_EXTENDED and len(data) == 2 and data[1] in PARAMS
        return WristCommand(Command.GET_EXTENDED, module, PARAMS[data[1]]) if ok else None
    if data[0] in SIMPLE:
        return WristCommand(SIMPLE[data[0]], module) if len(data) == 1 else None
    if len(data) != 6:
        return None
    if data[0] == Command.SET_EXTENDED and data[1] in PARAMS:
        value = value_of(data[1], data[2:6])
        return None if value is None else WristCommand(Command.SET_EXTENDED, module,
                                                       PARAMS[data[1]], value)
    if data[0] == Command.SET_MOTION and data[1] in (Motion.FRAMP_MODE, Motion.FRAMP_ACK):
        value = value_of(Param.ACT_POS, data[2:6])
        return None if value is None else WristCommand(Command.SET_MOTION, module,
                                                       Motion(data[1]), value)
    return None


#: Data bytes rich in the values the layouts care about.
_BYTE = st.one_of(st.sampled_from([0x00, 0x01, 0x02, 0x04, 0x08, 0x0A, 0x0B, 0x0E, 0x27, 0x3C,
                                   0x41, 0x4F, 0x50, 0x64, 0x7F, 0x80, 0xFF]),
                  st.integers(0, 255))
bodies = st.lists(_BYTE, min_size=1, max_size=8).map(bytes)


@st.composite
def shaped(draw: st.DrawFn) -> CanFrame:
    """A frame laid out as one of the protocol's frames (id and body) with random values —
    random float bytes, any parameter id — so that decoding often succeeds."""
    module = draw(st.integers(1, 31))
    param = draw(st.sampled_from(sorted(PARAMS)))
    value = draw(st.binary(min_size=4, max_size=4))
    layouts = [
        (ACK + module, bytes((draw(st.sampled_from(sorted(SIMPLE))), OK))),
        (ACK + module, bytes((0x0A, param)) + value),
        (ACK + module, bytes((0x08, param, OK))),
        (ACK + module, bytes((0x0B, 0x04, OK))),
        (ACK + module, bytes((0x0B, 0x0E)) + value + draw(st.binary(min_size=2, max_size=2))),
        (PUT + module, bytes((draw(st.sampled_from(sorted(SIMPLE))),))),
        (ALL, bytes((draw(st.sampled_from(sorted(SIMPLE))),))),
        (GET + module, bytes((0x0A, param))),
        (PUT + module, bytes((0x08, param)) + value),
        (PUT + module, bytes((0x0B, draw(st.sampled_from([0x04, 0x0E])))) + value)]
    ident, data = draw(st.sampled_from(layouts))
    return CanFrame(ident, data)


own_ids = st.one_of(st.integers(1, 31).map(lambda m: ACK + m), st.integers(0, 31).map(
    lambda m: PUT + m), st.integers(0, 31).map(lambda m: GET + m), st.just(ALL))
foreign_ids = st.integers(0, 0x7FF)


@st.composite
def frames(draw: st.DrawFn) -> CanFrame:
    """A frame shaped as the protocol's, a frame on the wrist's ids with a random body, a valid
    frame with one data byte corrupted, or a foreign frame (any id, or a 29-bit id)."""
    kind = draw(st.sampled_from(['shaped', 'shaped', 'own', 'corrupted', 'foreign', 'extended']))
    if kind == 'shaped':
        return draw(shaped())
    if kind == 'own':
        return CanFrame(draw(own_ids), draw(bodies))
    if kind == 'foreign':
        return CanFrame(draw(foreign_ids), draw(bodies))
    if kind == 'extended':
        return CanFrame(draw(st.integers(0, 0x1FFFFFFF)), draw(bodies), True)
    module = draw(st.integers(1, 31))
    valid = draw(st.sampled_from([
        codec.encode_reply(WristReply(Command.GET_EXTENDED, module, Param.ACT_POS, 0.25)),
        codec.encode_reply(WristReply(Command.GET_EXTENDED, module, Param.CUBE_STATE, 0x8002)),
        codec.encode_reply(WristReply(Command.SET_MOTION, module, Motion.FRAMP_ACK, -0.5, 2, 0)),
        codec.encode_reply(WristReply(Command.SET_EXTENDED, module, Param.TARGET_VEL)),
        codec.encode_command(WristCommand(Command.SET_MOTION, module, Motion.FRAMP_MODE, 1.0)),
        codec.encode_command(WristCommand(Command.SET_EXTENDED, module, Param.TARGET_ACC, 4.0)),
        codec.encode_command(WristCommand(Command.HALT, module))]))
    index = draw(st.integers(0, len(valid.data) - 1))
    value = draw(st.integers(0, 255).filter(lambda v: v != valid.data[index]))
    return CanFrame(valid.arbitration_id,
                    valid.data[:index] + bytes((value,)) + valid.data[index + 1:])


def _decoded(decoder, frame: CanFrame) -> object | None:
    try:
        return decoder(frame)
    except CodecError:
        return None


@FUZZ
@given(frames())
def test_a_frame_decodes_to_what_it_holds_or_is_refused(frame: CanFrame) -> None:
    for decoder, expect in ((codec.decode_reply, expected_reply),
                            (codec.decode_command, expected_command)):
        want = expect(frame)
        event(f'{decoder.__name__}: {"refused" if want is None else "decoded"}')
        if want is None:
            with pytest.raises(CodecError):
                decoder(frame)
        else:
            assert decoder(frame) == want, (frame, want)


@FUZZ
@given(st.lists(frames(), max_size=20))
def test_a_stream_of_frames_gives_exactly_the_replies_it_holds(stream: list[CanFrame]) -> None:
    got = [reply for reply in (_decoded(codec.decode_reply, f) for f in stream) if reply]
    assert got == [want for want in map(expected_reply, stream) if want is not None]
