"""ptu_server: the PTU Server (WURDE guide 7.4) for a Directed Perception PTU-46.

One PTUnit stream named after the module (``-n``; the name also picks the ``<device>`` of
``ptu-config.xml``, read from ``-c`` or the config directory, :mod:`wurde_drivers.ptu.config`).

- **Requests** (the guide's BlindTeleop sets ``myPTUnit.requests.pan``/``tilt`` and calls
  ``publishRequest``): only the members a request set are applied, in this order —
  ``halt`` (true: both axes stop where they are and the rest of the request is ignored),
  ``velocity_mode``, ``pan_accel``/``tilt_accel``, ``pan_speed``/``tilt_speed``, then
  ``pan``/``tilt`` (ignored in velocity mode, where the signed speeds drive the axes). A member
  not set keeps its commanded value. Values are clamped to the unit's limits; a request with a
  value that is not finite is refused whole.
- **Info** says what was commanded after clamping and rounding to whole position steps, the
  unit's limits and resolution (locked to suppliers: they are read only), the mode, and
  ``halt`` (true from a halt until the next motion command).
- **Data**: measured pan and tilt, their velocities and whether the unit moves, read from the
  unit at the configured rate (10 Hz by default), stamped with the time of the reading; also as
  ``sensor_msgs/JointState`` on ``/<name>/joint_states``, with the unit's base frame at the
  ``<device>``'s ``mount-*`` on ``/tf_static`` (:mod:`wurde_drivers.ros_std_joints`).

The unit is (re)connected about once a second until it answers; a unit that stops answering is
logged once and no data is published until it is back. On reconnect the commanded settings are
sent again (the unit may have been power-cycled) — in velocity mode with zero speeds, so a unit
that comes back never starts moving by itself.
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
import time

from wurde_core import CommsManager, LockMode, Logger, Time
from wurde_core.interfaces import PTUnit

from ..errors import DeviceError, DeviceTimeout
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.retry import RetryGate
from ..ports.serial_link import SerialLink
from ..ros_std_joints import JointStatePublisher, pan_tilt_standard
from .codec import LimitHit
from .config import load_ptu_config
from .device import PtuDriver

#: Loop sleep and longest wait for the unit's asynchronous messages per loop (s).
LOOP_S = 0.02
#: Longest wait for one reply, and for a whole (re)connect: a silent unit must not hold the loop
#: past the heartbeat's TTL (1 s).
REPLY_TIMEOUT_S = 0.1
CONNECT_TIMEOUT_S = 0.5
#: Least time between two connection attempts (s).
RETRY_S = 1.0
#: The guide's chapter 1 (1.1.5) runs the PTU server as ``safePTUserver``, with no options, and
#: maps its PTUnit stream as ``SafePTUServer``: so named, without ``-n``, the module is
#: ``safePTUserver`` and its stream ``SafePTUServer``.
GUIDE_PROGRAM, GUIDE_STREAM = 'safePTUserver', 'SafePTUServer'

_READ_ONLY = ('pan_min', 'pan_max', 'tilt_min', 'tilt_max', 'pan_resolution', 'tilt_resolution')
_NUMBERS = ('pan', 'tilt', 'pan_speed', 'tilt_speed', 'pan_accel', 'tilt_accel')


@dataclasses.dataclass
class Commanded:
    """What the unit was last told (rad, rad/s, rad/s^2), as the info shows it."""

    pan: float
    tilt: float
    pan_speed: float
    tilt_speed: float
    pan_accel: float
    tilt_accel: float
    velocity_mode: bool = False
    halt: bool = False


class PtuModule:
    """The module's work between one PTUnit supplier and one :class:`PtuDriver`; one thread.

    :meth:`step` is called once per loop: (re)connects, applies requests, reads and publishes.
    """

    def __init__(self, device: PtuDriver, stream: PTUnit, logger: Logger, *, period: float,
                 joints: JointStatePublisher | None = None) -> None:
        """Nothing is connected yet: the first :meth:`step` tries.

        :param device: the unit (constructed, not connected).
        :param stream: the PTUnit supplier, registered, read-only info members locked.
        :param logger: where connection changes and limit hits are logged (each outage once).
        :param period: seconds between two readings published.
        :param joints: the standard mirror of each reading (``/N/joint_states``), if any.
        """
        self.device = device
        self.joints = joints
        self.stream = stream
        self.logger = logger
        self.label = f'PTU on {device.link.url}'
        self.period = period
        self.commanded: Commanded | None = None
        self.up = False
        self._reported = False      # the current outage has been logged
        self._ever_up = False
        self._retry = RetryGate(RETRY_S)
        self._next_read = 0.0
        self._position_speeds = (0.0, 0.0)
        self._info_pending = False
        self.readings = 0

    # -- connection ---------------------------------------------------------------------------
    def _down(self, what: str, error: Exception) -> None:
        self.up = False
        self._retry.later(time.monotonic())
        if not self._reported:
            self._reported = True
            # The device layer's errors name the port.
            self.logger.warn(f'PTU {what}: {error}; no data until it answers (retrying every '
                             f'{RETRY_S:g} s){self.device.link.fault_note()}')

    def _connect(self, now: float) -> None:
        if not self._retry.due(now):
            return
        try:
            self.device.connect(CONNECT_TIMEOUT_S)
            self._sync()
        except (DeviceTimeout, DeviceError) as error:
            self._down('is not there or not answering', error)
            return
        limits = self.device.limits
        self.logger.notice(
            f'{self.label} {"is back" if self._ever_up else "connected"}: pan '
            f'{limits.pan_min:.3f}..{limits.pan_max:.3f} rad, tilt {limits.tilt_min:.3f}..'
            f'{limits.tilt_max:.3f} rad, {limits.pan_resolution * 1e3:.4f} mrad per step')
        self.up, self._ever_up, self._reported = True, True, False
        self._next_read = time.monotonic()
        self._info_pending = True

    def _sync(self) -> None:
        """After a connect: read the unit's settings the first time, else command them again."""
        device, c = self.device, self.commanded
        if c is None:
            state = device.query()
            accel = [device.command(name).number for name in ('pa', 'ta')]
            if None in accel:
                raise DeviceError(f'PTU answered its acceleration without a number: {accel}')
            limits = device.limits
            self.commanded = Commanded(state.pan, state.tilt, state.pan_speed, state.tilt_speed,
                                       accel[0] * limits.pan_resolution,  # type: ignore[operator]
                                       accel[1] * limits.tilt_resolution)  # type: ignore[operator]
            self._position_speeds = (state.pan_speed, state.tilt_speed)
            return
        if c.velocity_mode:
            device.set_velocity_mode(True)
        c.pan_accel, c.tilt_accel = device.set_acceleration(c.pan_accel, c.tilt_accel)
        speeds = (0.0, 0.0) if c.velocity_mode else (c.pan_speed, c.tilt_speed)
        c.pan_speed, c.tilt_speed = device.set_speed(*speeds)
        if not c.velocity_mode:
            c.pan, c.tilt = device.set_position(c.pan, c.tilt)

    # -- requests -----------------------------------------------------------------------------
    def _requests(self) -> None:
        while self.stream.get_next_request():
            if not self.up:
                if not self._reported:
                    self.logger.warn(f'{self.label} not connected; request dropped')
                    self._reported = True
                continue
            assert self.commanded is not None
            request = self.stream.requests
            fields = set(request.ros_message().set_fields) or set(request.field_names())
            values = {name: getattr(request, name).get_value() for name in fields
                      if name in _NUMBERS or name in ('halt', 'velocity_mode')}
            bad = sorted(n for n in values if n in _NUMBERS and not math.isfinite(values[n]))
            if bad:
                self.logger.warn(f'{self.label}: request refused: {", ".join(bad)} not finite')
                continue
            before = dataclasses.replace(self.commanded)
            try:
                self._apply(values, self.commanded)
            except DeviceTimeout as error:
                self._down('is silent', error)
            except DeviceError as error:
                self.logger.warn(f'{self.label}: request not applied in full: {error}')
            if self.commanded != before:
                self._info_pending = True

    def _apply(self, values: dict[str, float | bool], c: Commanded) -> None:
        """Send what ``values`` asks, updating ``c`` as each command is acknowledged."""
        device = self.device
        if values.get('halt'):
            device.halt()
            state = device.query()
            c.pan, c.tilt, c.halt = state.pan, state.tilt, True
            if c.velocity_mode:
                c.pan_speed = c.tilt_speed = 0.0
            return
        mode = values.get('velocity_mode', c.velocity_mode)
        mode_changed = bool(mode) != c.velocity_mode
        if mode_changed:
            if not c.velocity_mode:
                self._position_speeds = (c.pan_speed, c.tilt_speed)
            device.set_velocity_mode(bool(mode))
            c.velocity_mode = bool(mode)
            # Entering velocity mode stands still; leaving it restores the position-mode speeds.
            c.pan_speed, c.tilt_speed = (0.0, 0.0) if c.velocity_mode else self._position_speeds
        if 'pan_accel' in values or 'tilt_accel' in values:
            c.pan_accel, c.tilt_accel = device.set_acceleration(
                float(values.get('pan_accel', c.pan_accel)),
                float(values.get('tilt_accel', c.tilt_accel)))
        if mode_changed or 'pan_speed' in values or 'tilt_speed' in values:
            c.pan_speed, c.tilt_speed = device.set_speed(
                float(values.get('pan_speed', c.pan_speed)),
                float(values.get('tilt_speed', c.tilt_speed)))
            c.halt = c.halt and not c.velocity_mode
        if not c.velocity_mode and ('pan' in values or 'tilt' in values):
            c.pan, c.tilt = device.set_position(float(values.get('pan', c.pan)),
                                                float(values.get('tilt', c.tilt)))
            c.halt = False

    # -- publishing ---------------------------------------------------------------------------
    def _publish_info(self) -> None:
        c, limits = self.commanded, self.device.limits
        assert c is not None
        info = self.stream.info
        for name, value in (dataclasses.asdict(c) | {
                'pan_min': limits.pan_min, 'pan_max': limits.pan_max,
                'tilt_min': limits.tilt_min, 'tilt_max': limits.tilt_max,
                'pan_resolution': limits.pan_resolution,
                'tilt_resolution': limits.tilt_resolution}).items():
            getattr(info, name).set_value(value)
        # Not sent while the module is not running: try again next loop.
        self._info_pending = not self.stream.publish_info()

    def _read(self, now: float) -> None:
        try:
            state = self.device.query()
        except (DeviceTimeout, DeviceError) as error:
            self._down('is silent', error)
            return
        data = self.stream.data
        data.pan, data.tilt = state.pan, state.tilt
        data.pan_velocity, data.tilt_velocity = state.pan_velocity, state.tilt_velocity
        data.moving = state.moving
        data.timestamp = Time(time.time() - (time.monotonic() - state.stamp))
        self.stream.publish_data()
        if self.joints is not None:
            self.joints.publish(pan=state.pan, tilt=state.tilt, pan_velocity=state.pan_velocity,
                                tilt_velocity=state.tilt_velocity, stamp=data.timestamp.get_seconds())
        self.readings += 1
        self._next_read += self.period
        if self._next_read < now:            # fell behind (a slow line): keep the rate from now
            self._next_read = now + self.period

    def step(self) -> None:
        """One loop's work; never blocks much longer than a connect or a reading."""
        now = time.monotonic()
        if not self.up:
            self._connect(now)
        self._requests()
        if self.up and self._info_pending:
            self._publish_info()
        now = time.monotonic()
        if self.up and now >= self._next_read:
            self._read(now)
        if self.up and self.device.link.is_open:
            wait = min(LOOP_S, max(0.0, self._next_read - time.monotonic()))
            for event in self.device.poll(wait):
                if isinstance(event, LimitHit):
                    self.logger.warn(f'{self.label}: {event.axis} axis hit its limit '
                                     '(with limits enforced: the unit may need a reset)')


PtuServer = PtuModule  # old name (docs/naming.md)


def main(argv: list[str] | None = None) -> int:
    """The PTU server program (``ptu_server``, or the guide's ``safePTUserver``).

    :param argv: the command line, program name first; None: ``sys.argv``.  Run as
        ``safePTUserver`` without ``-n``, the stream is the guide's ``SafePTUServer``.
    :returns: the exit status.
    """
    argv = list(sys.argv if argv is None else argv)
    guide = bool(argv) and os.path.basename(argv[0]) == GUIDE_PROGRAM
    manager = CommsManager(GUIDE_PROGRAM if guide else 'PTUServer')
    config = configured_device(manager, argv, 'ptu-config.xml', load_ptu_config)
    stream_name = GUIDE_STREAM if guide and manager.options.name is None else manager.name
    device = PtuDriver(SerialLink(config.port, config.baud, retry_s=RETRY_S),
                       reply_timeout=REPLY_TIMEOUT_S, reset_timeout=CONNECT_TIMEOUT_S,
                       connect_timeout=CONNECT_TIMEOUT_S)
    stream = PTUnit(stream_name)
    stream.set_auto_timestamp(False)
    # Every request in order: each sets only some members, so keeping just the latest of two
    # that arrive within one loop would lose the first's (a halt, a mode change).
    stream.set_queue_mode(True)
    for name in _READ_ONLY:
        getattr(stream.info, name).lock(LockMode.SUPPLIERS)
    logger = Logger(manager.name)
    manager.register_supplier(stream)
    manager.register_supplier(logger)
    set_loop(manager, LOOP_S)
    server = PtuModule(device, stream, logger, period=1.0 / config.rate,
                       joints=pan_tilt_standard(manager.node, manager.name, config.mount))
    return run_loop(manager, server.step, device.close)


if __name__ == '__main__':
    sys.exit(main())
