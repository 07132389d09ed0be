"""The pan/tilt wrist on a python-can virtual bus: two PowerCube-like modules with ramp motion.

A :class:`can.Listener` on its own ``can.Bus(interface='virtual', channel=...)`` (docs/protocols.md 5:
virtual buses on one channel see each other only inside one process, so the driver under test
runs in the same process). It answers the frames of :mod:`wurde_drivers.wrist.codec`:
Reset, Home, Halt, SetExtended / GetExtended of the parameters listed there, and ramp moves.

Motion (a thread advancing both axes every ``tick_s``): each axis ramps toward its target with
the commanded TargetVel and TargetAcc (capped by MaxVel and MaxAcc) along the profile the PTU
emulator and the dummy wrist share (:mod:`wurde_drivers.motion`), so it stops on the target.
Pluto Software Documentation 8.3: both velocity and acceleration must be > 0 for the position to
change; otherwise the axis stays where it is. Targets are clamped to [MinPos, MaxPos]. After Halt
an axis stops at once and refuses moves until Reset (PowerCube STATE_HALTED). Modules start homed
and at 0 (ours: assumed). Frames sent to all modules (id 0x100) are obeyed but not acknowledged
(ours: assumed).

State frames: on request (GetExtended), and with ``state_hz`` also unsolicited GetExtended
acknowledges of ActPos and ActVel at that rate (ours: a convenience of the emulator).

Faults: :attr:`silent` (answers and broadcasts nothing), :meth:`send_garbage` (frames on the
acknowledge ids that do not decode).
"""

from __future__ import annotations

import dataclasses
import math
import random
import threading
import time

import can

from ..errors import CodecError
from ..motion import ramp_step
from . import codec
from .codec import Command, Motion, Param, State

__all__ = ['Axis', 'WristEmulator']


@dataclasses.dataclass
class Axis:
    """One module: limits, commanded ramp and the current motion (rad, rad/s, rad/s^2)."""

    module: int
    min_pos: float
    max_pos: float
    max_vel: float
    max_acc: float
    position: float = 0.0
    velocity: float = 0.0
    target: float = 0.0
    target_vel: float = 0.0
    target_acc: float = 0.0
    halted: bool = False
    homed: bool = True

    def step(self, dt: float) -> None:
        """Advance the ramp by ``dt`` seconds."""
        vel = min(self.target_vel, self.max_vel)
        acc = min(self.target_acc, self.max_acc)
        if self.halted or vel <= 0 or acc <= 0:
            self.velocity = 0.0
            return
        self.position, self.velocity = ramp_step(self.position, self.velocity, self.target, vel, acc, dt)
        self.position = max(self.min_pos, min(self.max_pos, self.position))

    @property
    def state(self) -> int:
        """The CubeState word."""
        flags = State(0)
        if self.homed:
            flags |= State.HOME_OK
        if self.halted:
            flags |= State.HALTED
        if self.velocity != 0.0:
            flags |= State.MOTION
        elif self.position == self.target:
            flags |= State.RAMP_END
        return int(flags)

    def param(self, param: Param) -> float | int:
        values: dict[Param, float | int] = {
            Param.CUBE_STATE: self.state, Param.ACT_POS: self.position,
            Param.ACT_VEL: self.velocity, Param.MIN_POS: self.min_pos,
            Param.MAX_POS: self.max_pos, Param.MAX_VEL: self.max_vel,
            Param.MAX_ACC: self.max_acc, Param.TARGET_VEL: self.target_vel,
            Param.TARGET_ACC: self.target_acc}
        return values[param]


class WristEmulator(can.Listener):
    """Two modules, pan and tilt, on the virtual CAN channel ``channel``.

    Use as a context manager, or :meth:`start` and :meth:`stop` (idempotent).
    """

    def __init__(self, channel: str = 'wrist', *, pan_id: int = 1, tilt_id: int = 2,
                 pan_limits: tuple[float, float] = (-math.pi, math.pi),
                 tilt_limits: tuple[float, float] = (-math.pi / 2, math.pi / 2),
                 max_vel: float = 2.0, max_acc: float = 8.0, state_hz: float | None = None,
                 tick_s: float = 0.005) -> None:
        self.channel = channel
        self.axes = {pan_id: Axis(pan_id, *pan_limits, max_vel, max_acc),
                     tilt_id: Axis(tilt_id, *tilt_limits, max_vel, max_acc)}
        self.pan, self.tilt = self.axes[pan_id], self.axes[tilt_id]
        self.state_hz = state_hz
        self.tick_s = tick_s
        #: While set, the modules answer nothing and broadcast nothing.
        self.silent = threading.Event()
        self.frames_in = 0
        self.bad_frames = 0
        self.frames_out = 0
        self.error: BaseException | None = None
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._bus: can.BusABC | None = None
        self._notifier: can.Notifier | None = None
        self._thread = threading.Thread(target=self._run, name='WristEmulator', daemon=True)
        self._random = random.Random(8)

    # -- life cycle ---------------------------------------------------------------------------
    def start(self) -> 'WristEmulator':
        self._bus = can.Bus(interface='virtual', channel=self.channel)
        self._notifier = can.Notifier(self._bus, [self], timeout=0.05)
        self._thread.start()
        return self

    def stop(self) -> None:
        """Stop the motion thread, the notifier, then the bus (idempotent).

        This is also :meth:`can.Listener.stop`, which ``Notifier.stop`` calls back after joining
        its thread; the notifier is forgotten first so that call-back is harmless.
        """
        self._stop.set()
        if self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout=5.0)
        notifier, self._notifier = self._notifier, None
        if notifier is not None:
            notifier.stop()  # before bus.shutdown (docs/protocols.md 5)
        if self._bus is not None:
            self._bus.shutdown()
            self._bus = None

    def __enter__(self) -> 'WristEmulator':
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- faults -------------------------------------------------------------------------------
    def send_garbage(self, count: int = 1) -> None:
        """Send ``count`` frames on the modules' acknowledge ids that no decoder accepts."""
        for _ in range(count):
            module = self._random.choice(list(self.axes))
            junk = bytes([0x5A]) + self._random.randbytes(self._random.randint(0, 7))
            self._send(codec.CanFrame(codec.CANID_ACK + module, junk), force=True)

    # -- bus ----------------------------------------------------------------------------------
    def _send(self, frame: codec.CanFrame, *, force: bool = False) -> None:
        bus = self._bus
        if bus is None or (self.silent.is_set() and not force):
            return
        try:
            bus.send(can.Message(arbitration_id=frame.arbitration_id, data=frame.data,
                                 is_extended_id=False))
        except can.CanError:
            return
        self.frames_out += 1

    def on_message_received(self, msg: can.Message) -> None:
        self.frames_in += 1
        if self.silent.is_set() or msg.is_error_frame or msg.is_remote_frame:
            return
        try:
            cmd = codec.decode_command((msg.arbitration_id, bytes(msg.data), msg.is_extended_id))
        except CodecError:
            self.bad_frames += 1
            return
        if cmd.module == 0:
            with self._lock:
                for each in self.axes.values():
                    self._simple(each, cmd.command)
            return
        axis = self.axes.get(cmd.module)
        if axis is None:
            return  # another device's module
        reply = self._handle(axis, cmd)
        if reply is not None:
            self._send(codec.encode_reply(reply))

    def on_error(self, exc: Exception) -> None:
        self.error = exc

    def _simple(self, axis: Axis, command: Command) -> None:
        if command is Command.RESET:
            axis.halted = False
        elif command is Command.HALT:
            axis.halted, axis.velocity, axis.target = True, 0.0, axis.position
        elif command is Command.HOME and not axis.halted:
            axis.target, axis.target_vel, axis.target_acc = 0.0, axis.max_vel / 2, axis.max_acc
            axis.homed = True

    def _handle(self, axis: Axis, cmd: codec.WristCommand) -> codec.WristReply | None:
        with self._lock:
            if cmd.command in (Command.RESET, Command.HOME, Command.HALT):
                self._simple(axis, cmd.command)
                return codec.WristReply(cmd.command, axis.module)
            if cmd.command is Command.GET_EXTENDED:
                assert cmd.param is not None
                return codec.WristReply(cmd.command, axis.module, cmd.param,
                                        axis.param(Param(cmd.param)))
            if cmd.command is Command.SET_EXTENDED:
                return self._set(axis, cmd)
            # SetMotion: a ramp move (refused while halted; the acknowledge carries the state)
            assert cmd.value is not None
            if not axis.halted:
                axis.target = max(axis.min_pos, min(axis.max_pos, float(cmd.value)))
            if cmd.param == Motion.FRAMP_ACK:
                short = 0x01 if axis.halted or not axis.homed else 0
                short |= 0x10 if axis.velocity else 0x20
                return codec.WristReply(cmd.command, axis.module, Motion.FRAMP_ACK,
                                        axis.position, short, 0)
            return codec.WristReply(cmd.command, axis.module, Motion.FRAMP_MODE)

    @staticmethod
    def _set(axis: Axis, cmd: codec.WristCommand) -> codec.WristReply | None:
        value = float(cmd.value) if cmd.value is not None else 0.0
        names = {Param.TARGET_VEL: 'target_vel', Param.TARGET_ACC: 'target_acc',
                 Param.MIN_POS: 'min_pos', Param.MAX_POS: 'max_pos', Param.MAX_VEL: 'max_vel',
                 Param.MAX_ACC: 'max_acc'}
        name = names.get(Param(cmd.param)) if cmd.param is not None else None
        if name is None:
            return None  # read-only parameter: not acknowledged
        setattr(axis, name, value)
        return codec.WristReply(Command.SET_EXTENDED, axis.module, cmd.param)

    # -- motion thread ------------------------------------------------------------------------
    def _run(self) -> None:
        last = time.monotonic()
        next_state = last
        unstepped = 0.0
        try:
            while not self._stop.wait(self.tick_s):
                now = time.monotonic()
                # Whole steps of tick_s only: the shared motion profile stops exactly on the
                # target for steps of one length, and a late wake-up on a loaded machine must
                # not carry an axis past it (wurde_drivers.motion).
                unstepped += now - last
                with self._lock:
                    while unstepped >= self.tick_s:
                        unstepped -= self.tick_s
                        for axis in self.axes.values():
                            axis.step(self.tick_s)
                    snapshot = [(a.module, a.position, a.velocity) for a in self.axes.values()]
                last = now
                if self.state_hz and now >= next_state:
                    next_state = max(next_state + 1.0 / self.state_hz, now)
                    for module, position, velocity in snapshot:
                        for param, value in ((Param.ACT_POS, position), (Param.ACT_VEL, velocity)):
                            self._send(codec.encode_reply(codec.WristReply(
                                Command.GET_EXTENDED, module, param, value)))
        except BaseException as error:  # kept for the test to see
            self.error = error
            raise
