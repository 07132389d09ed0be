"""The pan/tilt wrist driver over a python-can bus: ramp moves, halt, state polling; no ROS.

The caller opens the bus from a python-can interface and channel (``can.Bus(interface='virtual',
channel='wrist')`` in tests, ``interface='socketcan'`` on the robot) and hands it over; the driver
owns it from then on and shuts it down in :meth:`WristDriver.close` (docs/protocols.md 5: always
``bus.shutdown()``; 11-bit ids, ``is_extended_id=False``, on both sides). The frames are those of
:mod:`wurde_drivers.wrist.codec` (PowerCube-style modules, see there what is confirmed).

Pluto Software Documentation 8.3: command and state are (pan, tilt) in rad, rad/s, rad/s^2, and
"one must set both the velocity and acceleration > 0 if you want the position to change" -- the
driver passes what it is given; the modules do not move on a zero velocity or acceleration.

Life cycle: construct (no I/O) -> :meth:`connect` (may raise) -> :meth:`poll` in a loop (never
blocks longer than asked, never raises on bad frames; it asks the modules for their state every
``request_period`` seconds) -> :meth:`close` (idempotent).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable

import can

from ..errors import CodecError, DeviceTimeout
from . import codec
from .codec import Command, Param, State

__all__ = ['WristDriver', 'WristState', 'WristStats']

_STATE_PARAMS = (Param.ACT_POS, Param.ACT_VEL, Param.CUBE_STATE)


@dataclasses.dataclass(frozen=True)
class WristState:
    """Where the wrist is: pan and tilt in rad, their velocities in rad/s, the modules' CubeState
    words (0 until first read) and the driver clock when the newest value arrived."""

    stamp: float
    pan: float
    tilt: float
    pan_velocity: float
    tilt_velocity: float
    pan_flags: int = 0
    tilt_flags: int = 0

    @property
    def halted(self) -> bool:
        """Either module is halted (it refuses moves until reset)."""
        return bool((self.pan_flags | self.tilt_flags) & State.HALTED)


@dataclasses.dataclass
class WristStats:
    """Frames in and out, and every kind of trouble, counted."""

    frames_in: int = 0
    frames_out: int = 0
    bad_frames: int = 0       # on our modules' acknowledge ids, but not decodable
    ignored_frames: int = 0   # other devices' frames on the same bus
    bus_errors: int = 0       # send or receive refused by the bus
    timeouts: int = 0

    def as_dict(self) -> dict[str, int]:
        return dataclasses.asdict(self)


class WristDriver:
    """Drives the two wrist modules on a CAN bus."""

    def __init__(self, bus: can.BusABC, *, pan_id: int = 1, tilt_id: int = 2,
                 request_period: float = 0.05,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Keep the bus and the settings; nothing is sent until :meth:`connect`.

        :param bus: an open python-can bus; the driver shuts it down in :meth:`close`.
        :param pan_id: module address of the pan axis (1..31).
        :param tilt_id: module address of the tilt axis (1..31).
        :param request_period: seconds between two state requests made by :meth:`poll`.
        :param clock: the time source for stamps and :attr:`silent_for`.
        """
        self.bus: can.BusABC | None = bus
        self.pan_id, self.tilt_id = pan_id, tilt_id
        self.request_period = request_period
        self.stats = WristStats()
        self._clock = clock
        self._values: dict[tuple[int, Param], float | int] = {}
        self._last_frame = clock()
        self._last_update = 0.0
        self._next_request = 0.0
        self._halted = False

    # -- status -------------------------------------------------------------------------------
    @property
    def silent_for(self) -> float:
        """Seconds since the last good frame from either module (or since construction)."""
        return self._clock() - self._last_frame

    @property
    def state(self) -> WristState | None:
        """The newest complete state, or None until position and velocity of both are known."""
        values = self._values
        try:
            return WristState(self._last_update,
                              float(values[self.pan_id, Param.ACT_POS]),
                              float(values[self.tilt_id, Param.ACT_POS]),
                              float(values[self.pan_id, Param.ACT_VEL]),
                              float(values[self.tilt_id, Param.ACT_VEL]),
                              int(values.get((self.pan_id, Param.CUBE_STATE), 0)),
                              int(values.get((self.tilt_id, Param.CUBE_STATE), 0)))
        except KeyError:
            return None

    # -- life cycle ---------------------------------------------------------------------------
    def connect(self, timeout: float = 1.0) -> WristState:
        """Reset both modules (clearing a halt) and wait for their state.

        :param timeout: seconds to wait for a complete state.
        :returns: the first complete state.
        :raises DeviceTimeout: no complete state within ``timeout`` seconds.
        """
        self.reset()
        deadline = time.monotonic() + timeout
        self._next_request = 0.0
        while (remaining := deadline - time.monotonic()) > 0:
            self.poll(min(remaining, self.request_period))
            if (state := self.state) is not None:
                return state
        self.stats.timeouts += 1
        raise DeviceTimeout(f'wrist modules {self.pan_id} and {self.tilt_id} did not answer')

    def close(self) -> None:
        """Shut the bus down (idempotent)."""
        bus, self.bus = self.bus, None
        if bus is not None:
            bus.shutdown()

    # -- commands -----------------------------------------------------------------------------
    def move(self, pan: float, tilt: float, pan_vel: float, tilt_vel: float, pan_acc: float,
             tilt_acc: float) -> None:
        """Ramp both axes to a position; a module halted by :meth:`halt` is reset first.

        :param pan: rad.
        :param tilt: rad.
        :param pan_vel: rad/s.
        :param tilt_vel: rad/s.
        :param pan_acc: rad/s².
        :param tilt_acc: rad/s².
        :raises CodecError: a value is not finite.
        """
        frames = (codec.encode_move(self.pan_id, pan, pan_vel, pan_acc)
                  + codec.encode_move(self.tilt_id, tilt, tilt_vel, tilt_acc))
        if self._halted:
            self.reset()
        for frame in frames:
            self._send(frame)

    def halt(self) -> None:
        """Stop both axes at once; they refuse moves until :meth:`reset` (or the next move)."""
        for module in (self.pan_id, self.tilt_id):
            self._send(codec.encode_command(codec.WristCommand(Command.HALT, module)))
        self._halted = True

    def reset(self) -> None:
        """Clear the modules' error and halt states."""
        for module in (self.pan_id, self.tilt_id):
            self._send(codec.encode_command(codec.WristCommand(Command.RESET, module)))
        self._halted = False

    def home(self) -> None:
        """Start the modules' homing procedure."""
        for module in (self.pan_id, self.tilt_id):
            self._send(codec.encode_command(codec.WristCommand(Command.HOME, module)))

    def request_state(self) -> None:
        """Ask both modules for position, velocity and state word (answers arrive in poll)."""
        for module in (self.pan_id, self.tilt_id):
            for param in _STATE_PARAMS:
                self._send(codec.encode_command(
                    codec.WristCommand(Command.GET_EXTENDED, module, param)))
        self._next_request = time.monotonic() + self.request_period

    def _send(self, frame: codec.CanFrame) -> None:
        if self.bus is None:
            self.stats.bus_errors += 1
            return
        try:
            self.bus.send(can.Message(arbitration_id=frame.arbitration_id, data=frame.data,
                                      is_extended_id=False))
        except can.CanError:
            self.stats.bus_errors += 1
            return
        self.stats.frames_out += 1

    # -- receiving ----------------------------------------------------------------------------
    def poll(self, timeout: float) -> WristState | None:
        """The newest state if a state frame arrived within ``timeout`` seconds, else None.

        Returns as soon as something new has arrived (after taking every frame already
        waiting). Bad frames are counted in :attr:`stats`, never raised.

        :param timeout: the longest wait in seconds.
        """
        deadline = time.monotonic() + timeout
        updated = False
        while self.bus is not None:
            now = time.monotonic()
            if updated and now >= deadline:
                break
            if now >= self._next_request:
                self.request_state()
            wait = 0.0 if updated else max(0.0, min(deadline, self._next_request) - now)
            try:
                msg = self.bus.recv(timeout=wait)
            except can.CanError:
                self.stats.bus_errors += 1
                break
            if msg is None:
                if updated or time.monotonic() >= deadline:
                    break
                continue
            updated = self._handle(msg) or updated
        if not updated:
            if timeout > 0:
                self.stats.timeouts += 1
            return None
        return self.state

    def _handle(self, msg: can.Message) -> bool:
        self.stats.frames_in += 1
        module = msg.arbitration_id - codec.CANID_ACK
        if msg.is_extended_id or module not in (self.pan_id, self.tilt_id):
            self.stats.ignored_frames += 1
            return False
        try:
            reply = codec.decode_reply((msg.arbitration_id, bytes(msg.data), False))
        except CodecError:
            self.stats.bad_frames += 1
            return False
        self._last_frame = self._clock()
        if reply.command is Command.GET_EXTENDED and reply.param in _STATE_PARAMS:
            assert reply.value is not None
            self._values[module, Param(reply.param)] = reply.value
        elif reply.command is Command.SET_MOTION and reply.value is not None:
            self._values[module, Param.ACT_POS] = reply.value
        else:
            return False
        self._last_update = self._last_frame
        return self.state is not None
