"""The wrist's CAN codec: golden frames from the PowerCube layout, round trips, fuzzing."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.wrist import codec as wc
from wurde_drivers.wrist.codec import (CanFrame, Command, Motion, Param, WristCommand,
                                            WristReply)

H = bytes.fromhex
# ids: 0x0E0 + module put, 0x0C0 + module get, 0x0A0 + module acknowledge, 0x100 all;
# floats IEEE-754 little-endian (1.0 = 00 00 80 3F, 0.5 = 00 00 00 3F, -1.5 = 00 00 C0 BF).
COMMANDS = [
    (CanFrame(0x0E1, H('00')), WristCommand(Command.RESET, 1)),
    (CanFrame(0x0E2, H('02')), WristCommand(Command.HALT, 2)),
    (CanFrame(0x0E1, H('01')), WristCommand(Command.HOME, 1)),
    (CanFrame(0x100, H('02')), WristCommand(Command.HALT, 0)),
    (CanFrame(0x0C1, H('0A3C')), WristCommand(Command.GET_EXTENDED, 1, Param.ACT_POS)),
    (CanFrame(0x0E1, H('084F0000803F')), WristCommand(Command.SET_EXTENDED, 1, Param.TARGET_VEL,
                                                      1.0)),
    (CanFrame(0x0E2, H('0B040000003F')), WristCommand(Command.SET_MOTION, 2, Motion.FRAMP_MODE,
                                                      0.5)),
]
REPLIES = [
    (CanFrame(0x0A1, H('0A3C0000C0BF')), WristReply(Command.GET_EXTENDED, 1, Param.ACT_POS, -1.5)),
    (CanFrame(0x0A2, H('0A2702800000')), WristReply(Command.GET_EXTENDED, 2, Param.CUBE_STATE,
                                                    0x8002)),
    (CanFrame(0x0A2, H('0B0464')), WristReply(Command.SET_MOTION, 2, Motion.FRAMP_MODE)),
    (CanFrame(0x0A1, H('0B0E0000803F2000')), WristReply(Command.SET_MOTION, 1, Motion.FRAMP_ACK,
                                                        1.0, 0x20, 0)),
    (CanFrame(0x0A1, H('0264')), WristReply(Command.HALT, 1)),
    (CanFrame(0x0A1, H('084F64')), WristReply(Command.SET_EXTENDED, 1, Param.TARGET_VEL)),
]


@pytest.mark.parametrize('frame, command', COMMANDS)
def test_golden_commands(frame: CanFrame, command: WristCommand) -> None:
    assert wc.encode_command(command) == frame
    assert wc.decode_command(frame) == command
    assert frame.is_extended is False


@pytest.mark.parametrize('frame, reply', REPLIES)
def test_golden_replies(frame: CanFrame, reply: WristReply) -> None:
    assert wc.encode_reply(reply) == frame
    assert wc.decode_reply(frame) == reply


def test_a_move_is_target_velocity_target_acceleration_then_ramp() -> None:
    assert wc.encode_move(3, 0.5, 1.0, -1.5) == [
        CanFrame(0x0E3, H('084F0000803F')), CanFrame(0x0E3, H('08500000C0BF')),
        CanFrame(0x0E3, H('0B040000003F'))]


@pytest.mark.parametrize('frame', [
    (0x0E1, H('00'), True),              # extended id
    (0x0E1, b'', False),                 # no data
    (0x0E1, H('0000'), False),           # reset with data
    (0x0E0, H('00'), False),             # module 0 on the put id
    (0x123, H('00'), False),             # not a command id
    (0x0C1, H('0A'), False),             # get without parameter
    (0x0C1, H('0A77'), False),           # unknown parameter
    (0x0E1, H('084F0000'), False),       # truncated value
    (0x0E1, H('084F0000C07F'), False),   # NaN
    (0x0E1, H('0B990000803F'), False),   # unknown motion
    (0x100, H('08'), False),             # set-extended to all
    (0x0E1, H('55'), False),             # unknown command
])
def test_bad_command_frames_raise_codec_error(frame: tuple) -> None:
    with pytest.raises(CodecError):
        wc.decode_command(frame)


@pytest.mark.parametrize('frame', [
    (0x0A1, H('02'), False),             # halt acknowledge without 0x64
    (0x0A0, H('0264'), False),           # module 0
    (0x0A1, H('0A3C0000'), False),       # truncated value
    (0x0A1, H('0B0E0000803F20'), False),  # FRAMP_ACK too short
    (0x0A1, H('5A'), False),             # unknown command
    (0x7FF + 1, H('0264'), False),       # not an 11-bit id
])
def test_bad_reply_frames_raise_codec_error(frame: tuple) -> None:
    with pytest.raises(CodecError):
        wc.decode_reply(frame)


def test_encode_refuses_bad_values() -> None:
    for command in (WristCommand(Command.SET_EXTENDED, 1, Param.TARGET_VEL, float('inf')),
                    WristCommand(Command.SET_EXTENDED, 1, Param.TARGET_VEL, 1e39),
                    WristCommand(Command.GET_EXTENDED, 32, Param.ACT_POS),
                    WristCommand(Command.GET_EXTENDED, 0, Param.ACT_POS),
                    WristCommand(Command.SET_EXTENDED, 1, Param.CUBE_STATE, -1)):
        with pytest.raises(CodecError):
            wc.encode_command(command)


modules = st.integers(1, 31)
floats32 = st.floats(width=32, allow_nan=False, allow_infinity=False)
float_params = st.sampled_from([p for p in Param if p not in wc.INT_PARAMS])


def _value(param: Param) -> st.SearchStrategy:
    return st.integers(0, 0xFFFFFFFF) if param in wc.INT_PARAMS else floats32


commands = st.one_of(
    st.builds(WristCommand, st.sampled_from([Command.RESET, Command.HOME, Command.HALT]),
              st.integers(0, 31)),
    st.builds(WristCommand, st.just(Command.GET_EXTENDED), modules, st.sampled_from(list(Param))),
    st.sampled_from(list(Param)).flatmap(lambda p: st.builds(
        WristCommand, st.just(Command.SET_EXTENDED), modules, st.just(p), _value(p))),
    st.builds(WristCommand, st.just(Command.SET_MOTION), modules, st.sampled_from(list(Motion)),
              floats32),
)
replies = st.one_of(
    st.builds(WristReply, st.sampled_from([Command.RESET, Command.HOME, Command.HALT]), modules),
    st.sampled_from(list(Param)).flatmap(lambda p: st.builds(
        WristReply, st.just(Command.GET_EXTENDED), modules, st.just(p), _value(p))),
    st.builds(WristReply, st.just(Command.SET_EXTENDED), modules, float_params),
    st.builds(WristReply, st.just(Command.SET_MOTION), modules, st.just(Motion.FRAMP_MODE)),
    st.builds(WristReply, st.just(Command.SET_MOTION), modules, st.just(Motion.FRAMP_ACK),
              floats32, st.integers(0, 255), st.integers(0, 255)),
)


@settings(max_examples=300, deadline=None)
@given(commands)
def test_command_round_trip(command: WristCommand) -> None:
    assert wc.decode_command(wc.encode_command(command)) == command


@settings(max_examples=300, deadline=None)
@given(replies)
def test_reply_round_trip(reply: WristReply) -> None:
    assert wc.decode_reply(wc.encode_reply(reply)) == reply


frames = st.tuples(st.integers(0, 0x7FF) | st.integers(-5, 0x2000), st.binary(max_size=10),
                   st.booleans())


@settings(max_examples=300, deadline=None)
@given(frames)
def test_random_frames_decode_or_raise_codec_error(frame: tuple) -> None:
    for decode in (wc.decode_command, wc.decode_reply):
        try:
            decoded = decode(frame)
        except CodecError:
            continue
        assert decoded.module in range(32)
