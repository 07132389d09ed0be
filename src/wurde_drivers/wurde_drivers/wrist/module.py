"""wrist_module: Pluto's wristModule (Pluto Software Documentation 8.3), the CAN pan/tilt unit.

One ActuatorState stream named after the module (``-n``, default PlutoWrist), exactly as the dummy
wrist: a consumer's request is the command -- position (pan, tilt) in rad, velocity in rad/s and
acceleration in rad/s^2 per axis, or cmdFlags < 0 to halt -- the info is the command being
executed, the data is the state (position and velocity read from the modules; acceleration the
change of velocity between two states, an estimate: the modules do not report it). 8.3: "one
must set both the velocity and acceleration > 0 if you want the position to change"; an axis
commanded without both keeps where it is (its target becomes its current position). Each state
also goes out as ``sensor_msgs/JointState`` on ``/<name>/joint_states``, and the wrist's base
frame at the ``<device>``'s ``mount-*`` on ``/tf_static`` (:mod:`wurde_drivers.ros_std_joints`).

Configuration: the ``<device>`` named like the module in ``wrist-config.xml``
(:mod:`wurde_drivers.wrist.config`; ``-c`` or the config directory) names a python-can interface
and channel (``socketcan`` / ``can0`` on the robot). The bus is opened and the modules reset and
read from inside the loop, again about once a second until they answer; the module never exits
for a missing device. Modules silent for :data:`SILENT_AFTER_S` are logged once and no state is
published while they are silent (never stale data); their return is logged.

**No-hardware mode, chosen by configuration:** with ``emulate="true"`` (``interface="virtual"``
only) the module hosts :class:`~wurde_drivers.wrist.emulator.WristEmulator` on the same virtual
channel in its own process -- python-can's virtual bus connects buses inside one process only
(docs/protocols.md 5) -- so there is no separate wrist emulator program. In that mode SIGUSR1 toggles
the emulated modules' silence, to try the module's fault handling.
"""

from __future__ import annotations

import signal
import sys
import time
from typing import Any

import can
from wurde_core import CommsManager, Logger, Time
from wurde_core.interfaces import ActuatorState

from ..errors import CodecError, DeviceTimeout
from ..module_setup import configured_device, run_loop, set_loop
from ..ports.retry import RetryGate
from ..ros_std_joints import JointStatePublisher, pan_tilt_standard
from .config import WristDevice, load_wrist_config
from .device import WristDriver, WristState
from .emulator import WristEmulator

__all__ = ['WristModule', 'WristRunner', 'main']

#: Loop sleep and the longest poll (commands wait at most about twice this).
SLEEP_S = 0.02
#: State requests to the modules, and states published, every this many seconds (20 Hz, as the
#: dummy wrist).
STATE_PERIOD_S = 0.05
#: Longest the loop blocks in one connection attempt (well under the 1 s heartbeat TTL).
CONNECT_TIMEOUT_S = 0.5
#: Seconds between two attempts to open the bus or reach the modules.
RETRY_S = 1.0
#: Modules that answered nothing for this long (ten state requests) are silent.
SILENT_AFTER_S = 0.5


def _pair(values: Any) -> list[float] | None:
    items = [float(v) for v in values]
    return items[:2] if len(items) >= 2 else None


class WristModule:
    """The module's work per loop turn: open and connect (again), commands, state, silence.

    :param device: the configured device.
    :param wrist: the module's ActuatorState supplier (auto-timestamp off).
    :param logger: where connection and silence changes are logged (once each).
    :param joints: the standard mirror of each published state, if any.
    """

    def __init__(self, device: WristDevice, wrist: ActuatorState, logger: Logger,
                 joints: JointStatePublisher | None = None) -> None:
        self.device = device
        self.joints = joints
        self.wrist = wrist
        self.logger = logger
        self.emulator: WristEmulator | None = None
        self.driver: WristDriver | None = None
        self.connected = False
        self.silent = False
        self._failures = 0
        self._retry = RetryGate(RETRY_S)
        self._next_publish = 0.0
        self._published: WristState | None = None
        self._fresh = False
        self._to_wall = time.time() - time.monotonic()

    # -- connection ---------------------------------------------------------------------------
    def _not_ready(self, reason: str) -> None:
        if self._failures == 0:
            self.logger.warn(f'wrist not ready: {reason}; trying again every {RETRY_S:g} s')
        self._failures += 1

    def _try_connect(self) -> None:
        if not self._retry.due(time.monotonic()):
            return
        d = self.device
        if d.emulate and self.emulator is None:
            self.emulator = WristEmulator(d.channel, pan_id=d.pan_id, tilt_id=d.tilt_id).start()
            self.logger.notice(f'emulate="true": hosting the emulated wrist on virtual channel '
                               f'"{d.channel}" (no hardware)')
        if self.driver is None:
            try:
                bus = can.Bus(interface=d.interface, channel=d.channel)
            except (can.CanError, OSError, ValueError, NotImplementedError, ImportError) as error:
                self._not_ready(f'cannot open {d.interface} channel {d.channel}: {error}')
                return
            self.driver = WristDriver(bus, pan_id=d.pan_id, tilt_id=d.tilt_id,
                                      request_period=STATE_PERIOD_S)
        try:
            state = self.driver.connect(CONNECT_TIMEOUT_S)
        except DeviceTimeout as error:
            self._not_ready(str(error))
            return
        self.connected = True
        self.logger.notice(f'wrist modules {d.pan_id} (pan) and {d.tilt_id} (tilt) answer on '
                           f'{d.interface} channel {d.channel}')
        self._publish_command([state.pan, state.tilt], [0.0, 0.0], [0.0, 0.0])

    # -- commands -----------------------------------------------------------------------------
    def _publish_command(self, position: list[float], velocity: list[float],
                         acceleration: list[float]) -> None:
        """The info is the command being executed."""
        info = self.wrist.info
        info.cmd_flags.set_value(0)
        info.position.set_value(position)
        info.velocity.set_value(velocity)
        info.acceleration.set_value(acceleration)
        info.force.set_value([])
        self.wrist.publish_info()

    def handle_requests(self) -> None:
        """Execute every waiting command (the newest wins, as they are carried out in order)."""
        while self.wrist.get_next_request():
            req = self.wrist.requests
            driver, state = self.driver, self.driver.state if self.driver else None
            if not self.connected or driver is None or state is None:
                self.logger.warn('no wrist yet; command ignored')
                continue
            if req.cmd_flags.get_value() < 0:
                driver.halt()
                self._publish_command([state.pan, state.tilt], [0.0, 0.0], [0.0, 0.0])
                continue
            target, speed, accel = (_pair(req.position.get_value()), _pair(req.velocity.get_value()),
                                    _pair(req.acceleration.get_value()))
            if target is None or speed is None or accel is None:
                self.logger.warn('command needs position, velocity and acceleration (pan, tilt); '
                                 'ignored')
                continue
            # Pluto 8.3: without velocity and acceleration > 0 an axis keeps its position.
            target = [t if v > 0 and a > 0 else here
                      for t, v, a, here in zip(target, speed, accel, (state.pan, state.tilt))]
            try:
                driver.move(target[0], target[1], speed[0], speed[1], accel[0], accel[1])
            except CodecError as error:
                self.logger.warn(f'command refused: {error}')
                continue
            self._publish_command(target, speed, accel)

    # -- state --------------------------------------------------------------------------------
    def step(self, timeout: float) -> bool:
        """One turn: connect if needed, else commands and a poll of up to ``timeout`` s; returns
        whether a state was published."""
        if not self.connected:
            self._try_connect()
            self.handle_requests()
            return False
        self.handle_requests()
        assert self.driver is not None
        if self.driver.poll(timeout) is not None:
            self._fresh = True
        now = time.monotonic()
        silent_for = self.driver.silent_for
        if silent_for > SILENT_AFTER_S:
            if not self.silent:
                self.silent = True
                self.logger.warn(f'wrist modules are silent (nothing for {silent_for:.1f} s); '
                                 'publishing nothing until they are back')
            return False
        if self.silent:
            self.silent = False
            self._published = None   # no acceleration across the gap
            # half a period: every value of the answered request round has been refreshed
            self._next_publish = now + STATE_PERIOD_S / 2
            self.logger.notice('wrist modules are back')
        if not self._fresh or now < self._next_publish:
            return False
        state = self.driver.state
        if state is None:
            return False
        self._next_publish = max(self._next_publish + STATE_PERIOD_S, now)
        self._fresh = False
        self._publish_state(state)
        return True

    def _publish_state(self, state: WristState) -> None:
        previous, self._published = self._published, state
        acceleration = [0.0, 0.0]
        if previous is not None and state.stamp > previous.stamp:
            dt = state.stamp - previous.stamp
            acceleration = [(state.pan_velocity - previous.pan_velocity) / dt,
                            (state.tilt_velocity - previous.tilt_velocity) / dt]
        data = self.wrist.data
        data.cmd_flags = 0
        data.position = [state.pan, state.tilt]
        data.velocity = [state.pan_velocity, state.tilt_velocity]
        data.acceleration = acceleration
        data.force = []
        data.timestamp = Time(state.stamp + self._to_wall)
        self.wrist.publish_data()
        if self.joints is not None:
            self.joints.publish(pan=state.pan, tilt=state.tilt, pan_velocity=state.pan_velocity,
                                tilt_velocity=state.tilt_velocity, stamp=state.stamp + self._to_wall)

    # -- fault injection and shutdown ---------------------------------------------------------
    def toggle_emulated_silence(self) -> None:
        """Silence the hosted emulator, or end its silence (emulate mode only)."""
        if self.emulator is None:
            return
        if self.emulator.silent.is_set():
            self.emulator.silent.clear()
        else:
            self.emulator.silent.set()

    def close(self) -> None:
        """Shut the bus down, then the hosted emulator (idempotent)."""
        driver, self.driver = self.driver, None
        if driver is not None:
            driver.close()
        emulator, self.emulator = self.emulator, None
        if emulator is not None:
            emulator.stop()
        self.connected = False


WristRunner = WristModule  # old name (docs/naming.md)


def main(argv: list[str] | None = None) -> int:
    """The ``wrist_module`` program: one ``<device>`` of wrist-config.xml as an ActuatorState stream.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoWrist')
    device = configured_device(manager, argv, 'wrist-config.xml', load_wrist_config)
    wrist = ActuatorState(manager.name)
    wrist.set_auto_timestamp(False)
    runner = WristModule(device, wrist, Logger(manager.name))
    manager.register_supplier(wrist)
    manager.register_supplier(runner.logger)
    runner.joints = pan_tilt_standard(manager.node, manager.name, device.mount)   # the node exists now
    set_loop(manager, SLEEP_S)
    if device.emulate:
        signal.signal(signal.SIGUSR1, lambda _signum, _frame: runner.toggle_emulated_silence())

    def step() -> None:
        runner.step(SLEEP_S)

    return run_loop(manager, step, runner.close)


if __name__ == '__main__':
    sys.exit(main())
