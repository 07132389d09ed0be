"""The pan/tilt wrist's CAN frames: pure encode/decode over ``(arbitration_id, data, is_extended)``.

Pluto Software Documentation 8.3 says only that the wrist is on CAN and is driven in (pan, tilt)
position, velocity and acceleration. Which modules it is made of is not in the seed: we assume a
pair of Amtec PowerCube rotary modules (common on robots of that time and place) and speak their
protocol. No python-can import here: a frame is a :class:`CanFrame` tuple.

*From public PowerCube driver sources* (RobWork ``PCubeProtocol.hpp`` / ``Cube.cpp``, and other
PowerCube headers): 11-bit ids 0x0E0 + module (host -> module "put"), 0x0C0 + module (host ->
module "get"), 0x0A0 + module (module -> host acknowledge), 0x100 (to all modules); module
addresses 1..31; command bytes Reset 0x00, Home 0x01, Halt 0x02, SetExtended 0x08 (parameter id,
value), GetExtended 0x0A (parameter id), SetMotion 0x0B (motion id, value); motion FRAMP_MODE
0x04 (ramp to a float position, acknowledged as ``0B 04 64``) and FRAMP_ACK 0x0E (acknowledged
with the position, the short state and the digital I/O byte); parameters ActPos 0x3C, ActVel
0x41, CubeState 0x27 (uint32 flags), MinPos 0x45, MaxPos 0x46, MaxVel 0x48, MaxAcc 0x4A,
TargetVel 0x4F, TargetAcc 0x50; a GetExtended answer is ``0A <param> <4 value bytes>``; floats
and integers are IEEE-754 / two's complement, little-endian (the sources use an x86 union).

*Our assumptions* (not confirmed in a PowerCube manual): the acknowledge of SetExtended, Reset,
Home and Halt echoes the command and parameter bytes followed by 0x64; the module ids of pan (1)
and tilt (2); values are finite (a non-finite float is refused).
"""

from __future__ import annotations

import dataclasses
import enum
import math
import struct
from typing import NamedTuple

from ..errors import CodecError

__all__ = [
    'ACK_OK', 'CANID_ACK', 'CANID_ALL', 'CANID_GET', 'CANID_PUT', 'INT_PARAMS', 'CanFrame',
    'Command', 'Motion', 'Param', 'State', 'WristCommand', 'WristReply', 'decode_command',
    'decode_reply', 'encode_command', 'encode_move', 'encode_reply',
]

CANID_ACK = 0x0A0
CANID_GET = 0x0C0
CANID_PUT = 0x0E0
CANID_ALL = 0x100
ACK_OK = 0x64


class CanFrame(NamedTuple):
    """One classic CAN frame with an 11-bit id."""

    arbitration_id: int
    data: bytes
    is_extended: bool = False


class Command(enum.IntEnum):
    RESET = 0x00
    HOME = 0x01
    HALT = 0x02
    SET_EXTENDED = 0x08
    GET_EXTENDED = 0x0A
    SET_MOTION = 0x0B


class Motion(enum.IntEnum):
    FRAMP_MODE = 0x04
    FRAMP_ACK = 0x0E


class Param(enum.IntEnum):
    CUBE_STATE = 0x27
    ACT_POS = 0x3C
    ACT_VEL = 0x41
    MIN_POS = 0x45
    MAX_POS = 0x46
    MAX_VEL = 0x48
    MAX_ACC = 0x4A
    TARGET_VEL = 0x4F
    TARGET_ACC = 0x50


class State(enum.IntFlag):
    """Bits of the CubeState word (PowerCube sources)."""

    ERROR = 0x1
    HOME_OK = 0x2
    HALTED = 0x4
    MOTION = 0x800
    RAMP_END = 0x8000
    BEYOND_SOFT = 0x04000000


#: Parameters carried as uint32; every other one is a float32.
INT_PARAMS = frozenset({Param.CUBE_STATE})
_SIMPLE = (Command.RESET, Command.HOME, Command.HALT)


@dataclasses.dataclass(frozen=True)
class WristCommand:
    """A host -> module frame. ``module`` 0 means all modules (only Reset, Home, Halt);
    ``param`` is the parameter id (SetExtended, GetExtended) or the motion id (SetMotion)."""

    command: Command
    module: int
    param: int | None = None
    value: float | int | None = None


@dataclasses.dataclass(frozen=True)
class WristReply:
    """A module -> host acknowledge: GetExtended carries ``value``; FRAMP_ACK carries the
    position in ``value`` and the short state and I/O bytes in ``state`` and ``io``."""

    command: Command
    module: int
    param: int | None = None
    value: float | int | None = None
    state: int | None = None
    io: int | None = None


def _pack_value(param: int, value: float | int | None) -> bytes:
    if value is None:
        raise CodecError(f'parameter 0x{param:02X} needs a value')
    if param in INT_PARAMS:
        if not isinstance(value, int) or not 0 <= value <= 0xFFFFFFFF:
            raise CodecError(f'parameter 0x{param:02X} is a uint32, got {value!r}')
        return struct.pack('<I', value)
    if not math.isfinite(value):
        raise CodecError(f'cannot send non-finite value {value!r}')
    try:
        return struct.pack('<f', value)
    except OverflowError as error:
        raise CodecError(f'{value!r} does not fit a float32') from error


def _unpack_value(param: int, data: bytes) -> float | int:
    if param in INT_PARAMS:
        return int(struct.unpack('<I', data)[0])
    value = float(struct.unpack('<f', data)[0])
    if not math.isfinite(value):
        raise CodecError(f'non-finite float for parameter 0x{param:02X}')
    return value


def _param(raw: int) -> Param:
    try:
        return Param(raw)
    except ValueError:
        raise CodecError(f'unknown PowerCube parameter 0x{raw:02X}') from None


def _motion(raw: int) -> Motion:
    try:
        return Motion(raw)
    except ValueError:
        raise CodecError(f'unsupported PowerCube motion 0x{raw:02X}') from None


def _check_module(module: int) -> None:
    if not 1 <= module <= 31:
        raise CodecError(f'PowerCube module address must be 1..31, got {module}')


def encode_command(cmd: WristCommand) -> CanFrame:
    """The frame for ``cmd``.

    :param cmd: a host -> module command.
    :raises CodecError: bad module, parameter, motion or value.
    """
    if cmd.module == 0:
        if cmd.command not in _SIMPLE:
            raise CodecError(f'{cmd.command.name} cannot be sent to all modules')
        return CanFrame(CANID_ALL, bytes([cmd.command]))
    _check_module(cmd.module)
    if cmd.command in _SIMPLE:
        return CanFrame(CANID_PUT + cmd.module, bytes([cmd.command]))
    if cmd.param is None:
        raise CodecError(f'{cmd.command.name} needs a parameter or motion id')
    if cmd.command is Command.GET_EXTENDED:
        return CanFrame(CANID_GET + cmd.module, bytes([cmd.command, _param(cmd.param)]))
    if cmd.command is Command.SET_EXTENDED:
        param = _param(cmd.param)
        return CanFrame(CANID_PUT + cmd.module,
                        bytes([cmd.command, param]) + _pack_value(param, cmd.value))
    motion = _motion(cmd.param)
    return CanFrame(CANID_PUT + cmd.module,
                    bytes([cmd.command, motion]) + _pack_value(Param.ACT_POS, cmd.value))


def encode_move(module: int, position: float, velocity: float,
                acceleration: float) -> list[CanFrame]:
    """The three frames of one ramp move: TargetVel, TargetAcc, then ramp to ``position``.

    :param module: the module's address.
    :param position: the target, rad.
    :param velocity: rad/s.
    :param acceleration: rad/s².
    :raises CodecError: a value that is not finite, or a bad module.
    """
    return [encode_command(WristCommand(Command.SET_EXTENDED, module, Param.TARGET_VEL, velocity)),
            encode_command(WristCommand(Command.SET_EXTENDED, module, Param.TARGET_ACC,
                                        acceleration)),
            encode_command(WristCommand(Command.SET_MOTION, module, Motion.FRAMP_MODE, position))]


def _check_frame(frame: tuple[int, bytes, bool]) -> tuple[int, bytes]:
    try:
        arbitration_id, data, extended = frame
    except (TypeError, ValueError) as error:
        raise CodecError(f'not a CAN frame: {frame!r}') from error
    if extended:
        raise CodecError('the wrist uses 11-bit ids only')
    if not isinstance(arbitration_id, int) or not 0 <= arbitration_id <= 0x7FF:
        raise CodecError(f'not an 11-bit CAN id: {arbitration_id!r}')
    try:
        data = bytes(data)
    except (TypeError, ValueError) as error:
        raise CodecError(f'CAN data must be bytes: {data!r}') from error
    if not 1 <= len(data) <= 8:
        raise CodecError(f'CAN data must be 1..8 bytes, got {len(data)}')
    return arbitration_id, data


def _command_id(raw: int) -> Command:
    try:
        return Command(raw)
    except ValueError:
        raise CodecError(f'unknown PowerCube command 0x{raw:02X}') from None


def decode_command(frame: tuple[int, bytes, bool]) -> WristCommand:
    """The host -> module command in ``frame``.

    :param frame: (arbitration id, data, is_extended_id).
    :raises CodecError: not a command frame of this protocol.
    """
    arbitration_id, data = _check_frame(frame)
    command = _command_id(data[0])
    if arbitration_id == CANID_ALL:
        if command not in _SIMPLE or len(data) != 1:
            raise CodecError(f'bad all-modules frame {data.hex()}')
        return WristCommand(command, 0)
    base = arbitration_id & ~0x1F
    module = arbitration_id & 0x1F
    if base not in (CANID_PUT, CANID_GET) or module == 0:
        raise CodecError(f'0x{arbitration_id:03X} is not a command id')
    if base == CANID_GET:
        if command is not Command.GET_EXTENDED or len(data) != 2:
            raise CodecError(f'bad get frame {data.hex()}')
        return WristCommand(command, module, _param(data[1]))
    if command in _SIMPLE:
        if len(data) != 1:
            raise CodecError(f'{command.name} takes no data')
        return WristCommand(command, module)
    if command is Command.SET_EXTENDED and len(data) == 6:
        param = _param(data[1])
        return WristCommand(command, module, param, _unpack_value(param, data[2:6]))
    if command is Command.SET_MOTION and len(data) == 6:
        return WristCommand(command, module, _motion(data[1]),
                            _unpack_value(Param.ACT_POS, data[2:6]))
    raise CodecError(f'bad {command.name} frame {data.hex()}')


def encode_reply(reply: WristReply) -> CanFrame:
    """The acknowledge frame for ``reply``.

    :param reply: a module -> host acknowledge.
    :raises CodecError: bad module, parameter or value.
    """
    _check_module(reply.module)
    arbitration_id = CANID_ACK + reply.module
    if reply.command in _SIMPLE:
        return CanFrame(arbitration_id, bytes([reply.command, ACK_OK]))
    if reply.param is None:
        raise CodecError(f'{reply.command.name} acknowledge needs a parameter or motion id')
    if reply.command is Command.GET_EXTENDED:
        param = _param(reply.param)
        return CanFrame(arbitration_id, bytes([reply.command, param])
                        + _pack_value(param, reply.value))
    if reply.command is Command.SET_EXTENDED:
        return CanFrame(arbitration_id, bytes([reply.command, _param(reply.param), ACK_OK]))
    motion = _motion(reply.param)
    if motion is Motion.FRAMP_MODE:
        return CanFrame(arbitration_id, bytes([reply.command, motion, ACK_OK]))
    if reply.state is None or reply.io is None or not (0 <= reply.state <= 255
                                                          and 0 <= reply.io <= 255):
        raise CodecError('FRAMP_ACK acknowledge needs state and io bytes')
    return CanFrame(arbitration_id, bytes([reply.command, motion])
                    + _pack_value(Param.ACT_POS, reply.value) + bytes([reply.state, reply.io]))


def decode_reply(frame: tuple[int, bytes, bool]) -> WristReply:
    """The module -> host acknowledge in ``frame``.

    :param frame: (arbitration id, data, is_extended_id).
    :raises CodecError: not an acknowledge frame of this protocol.
    """
    arbitration_id, data = _check_frame(frame)
    module = arbitration_id - CANID_ACK
    if not 1 <= module <= 31:
        raise CodecError(f'0x{arbitration_id:03X} is not an acknowledge id')
    command = _command_id(data[0])
    if command in _SIMPLE:
        if data[1:] != bytes([ACK_OK]):
            raise CodecError(f'bad {command.name} acknowledge {data.hex()}')
        return WristReply(command, module)
    if len(data) < 2:
        raise CodecError(f'{command.name} acknowledge too short')
    if command is Command.GET_EXTENDED:
        param = _param(data[1])
        if len(data) != 6:
            raise CodecError(f'GetExtended acknowledge must be 6 bytes, got {len(data)}')
        return WristReply(command, module, param, _unpack_value(param, data[2:6]))
    if command is Command.SET_EXTENDED:
        if len(data) != 3 or data[2] != ACK_OK:
            raise CodecError(f'bad SetExtended acknowledge {data.hex()}')
        return WristReply(command, module, _param(data[1]))
    motion = _motion(data[1])
    if motion is Motion.FRAMP_MODE:
        if len(data) != 3 or data[2] != ACK_OK:
            raise CodecError(f'bad FRAMP_MODE acknowledge {data.hex()}')
        return WristReply(command, module, motion)
    if len(data) != 8:
        raise CodecError(f'FRAMP_ACK acknowledge must be 8 bytes, got {len(data)}')
    return WristReply(command, module, motion, _unpack_value(Param.ACT_POS, data[2:6]),
                      data[6], data[7])
