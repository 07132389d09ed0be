"""dummy_wrist: Pluto's dummy wrist (5, 8.3): a pan/tilt unit that moves as commanded.

One ActuatorState stream named after the module (``-n``, default the config's wrist name): a
consumer's request is the command — position (pan, tilt) in rad, velocity and acceleration per
axis, both > 0 for the position to change — and the data is the state: current position,
velocity and acceleration. Motion is trapezoidal within the configured limits, in simulated time.
The state also goes out as ``sensor_msgs/JointState`` on ``/<name>/joint_states``, and the wrist's
base frame at the config's ``mount-*`` on ``/tf_static`` (:mod:`wurde_drivers.ros_std_joints`).
Idle (guide 5.2.1) brings it to rest, as the dummy base; back in Run its time jumps to now, and a
starved loop drops steps rather than catch up for long (it must reach a Quit promptly).
"""

from __future__ import annotations

import sys
import time

from wurde_core import CommsManager, Logger, RunState, Time
from wurde_core.interfaces import ActuatorState

from ...module_setup import set_loop
from ...ros_std_joints import pan_tilt_standard
from ..axis import Axis
from ..clock import SimClock
from ..config import WristConfig
from ..loading import read_sim_config

STEP_S = 0.01
#: Most simulation steps one loop may run before it gives up catching up (as the dummy base): a
#: starved loop must still reach ``run_update`` (and a Quit) often.
MAX_CATCH_UP = 200
#: Longest an Idle stop may take (s of simulated time).
MAX_STOP_S = 5.0


def _pair(values: object) -> list[float] | None:
    items = [float(v) for v in values]  # type: ignore[attr-defined]
    return items[:2] if len(items) >= 2 else None


def main(argv: list[str] | None = None) -> int:
    """The ``dummy_wrist`` program: the sim-config's ``<wrist>`` on the simulated robot.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (2 for a bad config, with ``file:line: reason`` on stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('PlutoWrist')
    config = read_sim_config(manager, argv)
    wc = config.wrist or WristConfig()
    axes = [Axis(wc.pan_min, wc.pan_max, wc.max_velocity, wc.max_acceleration),
            Axis(wc.tilt_min, wc.tilt_max, wc.max_velocity, wc.max_acceleration)]
    logger = Logger(manager.name)
    wrist = ActuatorState(manager.name)
    wrist.set_auto_timestamp(False)
    manager.register_supplier(wrist)
    manager.register_supplier(logger)
    joints = pan_tilt_standard(manager.node, manager.name, wc.mount)
    set_loop(manager, min(0.02, 1.0 / wc.rate / config.time_scale / 2))
    clock = SimClock(step_s=STEP_S, time_scale=config.time_scale, start=time.time())
    publish_every = max(1, round(1.0 / (wc.rate * STEP_S)))
    wall0 = time.monotonic()
    # With use_sim_time the simulator's /clock drives the wrist (its stamps then agree with the
    # base's at any time scale); else its own clock runs at the time scale against the wall.
    use_sim_time = bool(manager.node.get_parameter('use_sim_time').value)
    clock_started = False

    def target_steps() -> int:
        nonlocal clock_started
        if not use_sim_time:
            return int((time.monotonic() - wall0) * config.time_scale / STEP_S)
        now = manager.now().get_seconds()
        if now <= 0.0:
            return clock.steps                  # no /clock yet
        if not clock_started:
            clock.start, clock_started = now, True
        return int((now - clock.start) / STEP_S)

    def hold_for_idle() -> None:
        """Idle (guide 5.2.1): the wrist must not move on unattended; bring it to rest now."""
        for axis in axes:
            axis.halt()
        for _ in range(int(MAX_STOP_S / STEP_S)):
            if not any(axis.moving for axis in axes):
                break
            for axis in axes:
                axis.step(clock.tick() if axis is axes[0] else STEP_S)

    def resume() -> None:
        """Back in Run: the wrist stood still while Idle; simulated time jumps to now (no burst
        of back-dated states).  The command executed now is the stop Idle made."""
        clock.steps = max(clock.steps, target_steps())
        _publish_command(wrist, axes)

    manager.on_state(RunState.IDLE, hold_for_idle)
    manager.on_state(RunState.RUN, resume)
    _publish_command(wrist, axes)
    while manager.run_update() == RunState.RUN:
        while wrist.get_next_request():
            req = wrist.requests
            target, speed, accel = (_pair(req.position.get_value()), _pair(req.velocity.get_value()),
                                    _pair(req.acceleration.get_value()))
            if req.cmd_flags.get_value() < 0:
                for axis in axes:
                    axis.halt()
            elif target is None or speed is None or accel is None:
                logger.warn(f'{manager.name}: command needs position, velocity and acceleration '
                            '(pan, tilt); ignored')
                continue
            else:
                for axis, t, s, a in zip(axes, target, speed, accel):
                    axis.command(t, s, a)
            _publish_command(wrist, axes)
        due = target_steps()
        if due - clock.steps > MAX_CATCH_UP:
            logger.warn(f'{manager.name}: {due - clock.steps} steps behind; dropping them')
            clock.steps = due - 1
        while clock.steps < due:
            for axis in axes:
                axis.step(clock.tick() if axis is axes[0] else STEP_S)
            if clock.steps % publish_every == 0:
                data = wrist.data
                data.cmd_flags = 0
                data.position = [a.position for a in axes]
                data.velocity = [a.velocity for a in axes]
                data.acceleration = [a.acceleration for a in axes]
                data.force = []
                data.timestamp = Time(clock.now)
                wrist.publish_data()
                joints.publish(pan=axes[0].position, tilt=axes[1].position, pan_velocity=axes[0].velocity,
                               tilt_velocity=axes[1].velocity, stamp=clock.now)
    manager.clean_up(exiting=True)
    return 0


def _publish_command(wrist: ActuatorState, axes: list[Axis]) -> None:
    """The info is the command being executed (targets, speeds, accelerations)."""
    wrist.info.cmd_flags.set_value(0)
    wrist.info.position.set_value([a.target for a in axes])
    wrist.info.velocity.set_value([a.speed for a in axes])
    wrist.info.acceleration.set_value([a.accel for a in axes])
    wrist.info.force.set_value([])
    wrist.publish_info()


if __name__ == '__main__':
    sys.exit(main())
