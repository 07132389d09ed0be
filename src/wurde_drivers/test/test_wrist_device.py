"""The wrist driver against the wrist emulator on python-can's virtual bus (one process)."""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Iterator

import can
import pytest

from wurde_drivers.errors import DeviceTimeout
from wurde_drivers.wrist.device import WristDriver, WristState
from wurde_drivers.wrist.emulator import WristEmulator

_channels = itertools.count()


@pytest.fixture
def channel() -> str:
    return f'wrist-test-{next(_channels)}'


@pytest.fixture
def emulator(channel: str) -> Iterator[WristEmulator]:
    with WristEmulator(channel) as device:
        yield device
    assert device.error is None


@pytest.fixture
def driver(channel: str, emulator: WristEmulator) -> Iterator[WristDriver]:
    wrist = WristDriver(can.Bus(interface='virtual', channel=channel), request_period=0.02)
    try:
        yield wrist
    finally:
        wrist.close()


def wait_for(driver: WristDriver, condition: Callable[[WristState], bool],
             within: float = 20.0) -> WristState:
    deadline = time.monotonic() + within
    last = None
    while time.monotonic() < deadline:
        state = driver.poll(0.05)
        if state is not None:
            last = state
            if condition(state):
                return state
    raise AssertionError(f'condition not met within {within} s; last state {last}')


def test_default_channel_is_wrist() -> None:
    with WristEmulator() as emulator:
        wrist = WristDriver(can.Bus(interface='virtual', channel='wrist'))
        try:
            state = wrist.connect()
            assert emulator.channel == 'wrist' and state.pan == 0.0
        finally:
            wrist.close()


def test_connect_reads_the_state(driver: WristDriver) -> None:
    state = driver.connect()
    assert (state.pan, state.tilt, state.pan_velocity, state.tilt_velocity) == (0, 0, 0, 0)
    assert driver.stats.frames_out >= 2 and driver.stats.bad_frames == 0
    assert driver.silent_for < 0.5


def test_move_ramps_to_the_target_within_the_velocity_limit(driver: WristDriver) -> None:
    driver.connect()
    driver.move(0.6, -0.3, 1.0, 0.5, 4.0, 4.0)
    fastest = 0.0

    def arrived(state: WristState) -> bool:
        nonlocal fastest
        fastest = max(fastest, abs(state.pan_velocity))
        return (abs(state.pan - 0.6) < 1e-4 and abs(state.tilt + 0.3) < 1e-4
                and state.pan_velocity == 0 and state.tilt_velocity == 0)

    wait_for(driver, arrived)
    assert 0.0 < fastest <= 1.0 + 1e-6


@pytest.mark.parametrize('velocity, acceleration', [(0.0, 4.0), (1.0, 0.0), (0.0, 0.0)])
def test_no_motion_unless_velocity_and_acceleration_are_positive(
        driver: WristDriver, velocity: float, acceleration: float) -> None:
    driver.connect()
    driver.move(0.5, 0.5, velocity, velocity, acceleration, acceleration)
    end = time.monotonic() + 0.3                       # absence of motion: watch for a while
    seen = 0
    while time.monotonic() < end:
        state = driver.poll(0.05)
        if state is not None:
            seen += 1
            assert (state.pan, state.tilt) == (0.0, 0.0)
    assert seen >= 2


def test_targets_are_clamped_to_the_joint_limits(driver: WristDriver) -> None:
    driver.connect()
    driver.move(0.0, 3.0, 1.0, 2.0, 4.0, 8.0)
    state = wait_for(driver, lambda s: s.tilt_velocity == 0 and s.tilt > 1.0)
    assert state.tilt == pytest.approx(math.pi / 2, abs=1e-5)


def test_halt_stops_at_once_and_the_next_move_resets(driver: WristDriver) -> None:
    driver.connect()
    driver.move(2.5, 0.0, 1.0, 1.0, 4.0, 4.0)
    wait_for(driver, lambda s: s.pan > 0.3)
    driver.halt()
    halted = wait_for(driver, lambda s: s.halted and s.pan_velocity == 0)
    assert halted.pan < 2.0
    after = wait_for(driver, lambda s: s.stamp > halted.stamp + 0.1)
    assert after.pan == pytest.approx(halted.pan, abs=1e-6)
    driver.move(0.0, 0.0, 2.0, 2.0, 8.0, 8.0)
    wait_for(driver, lambda s: not s.halted and abs(s.pan) < 1e-4 and s.pan_velocity == 0)


def test_unsolicited_state_frames_are_used(channel: str) -> None:
    with WristEmulator(channel, state_hz=50.0) as emulator:
        wrist = WristDriver(can.Bus(interface='virtual', channel=channel), request_period=3600.0)
        try:
            wrist.connect()                           # one request, then broadcasts only
            emulator.pan.target, emulator.pan.target_vel, emulator.pan.target_acc = 0.2, 1, 4
            # Arrived and stopped, seen through the broadcasts alone: where it stops is the target.
            stopped = wait_for(wrist, lambda s: s.pan > 0.1 and s.pan_velocity == 0.0)
            assert stopped.pan == pytest.approx(0.2, abs=1e-4)
            assert wrist.stats.frames_out == 2 + 6    # the resets and one request
        finally:
            wrist.close()


def test_silent_wrist_times_out_and_comes_back(driver: WristDriver,
                                               emulator: WristEmulator) -> None:
    driver.connect()
    emulator.silent.set()
    deadline = time.monotonic() + 2.0
    while driver.poll(0.05) is not None and time.monotonic() < deadline:
        pass                                           # drain frames already in flight
    started = time.monotonic()
    assert driver.poll(0.2) is None
    assert 0.15 <= time.monotonic() - started < 1.0
    assert driver.silent_for >= 0.15 and driver.stats.timeouts >= 1
    emulator.silent.clear()
    wait_for(driver, lambda s: True)
    assert driver.silent_for < 0.5


def test_garbage_frames_are_counted_and_state_flows_on(driver: WristDriver,
                                                       emulator: WristEmulator) -> None:
    driver.connect()
    emulator.send_garbage(5)
    deadline = time.monotonic() + 2.0
    while driver.stats.bad_frames < 5 and time.monotonic() < deadline:
        driver.poll(0.05)
    assert driver.stats.bad_frames == 5
    driver.move(0.1, 0.1, 1.0, 1.0, 4.0, 4.0)
    wait_for(driver, lambda s: abs(s.pan - 0.1) < 1e-4 and abs(s.tilt - 0.1) < 1e-4)


def test_other_devices_frames_are_ignored(channel: str, driver: WristDriver) -> None:
    driver.connect()
    with can.Bus(interface='virtual', channel=channel) as other:
        other.send(can.Message(arbitration_id=0x181, data=b'\x01\x02', is_extended_id=False))
        deadline = time.monotonic() + 2.0
        while driver.stats.ignored_frames < 1 and time.monotonic() < deadline:
            driver.poll(0.05)
    assert driver.stats.ignored_frames >= 1 and driver.stats.bad_frames == 0


def test_connect_without_a_wrist_raises_device_timeout(channel: str) -> None:
    wrist = WristDriver(can.Bus(interface='virtual', channel=channel + '-empty'))
    started = time.monotonic()
    try:
        with pytest.raises(DeviceTimeout):
            wrist.connect(timeout=0.3)
        assert time.monotonic() - started < 0.3 + 1.5     # (slack for a loaded machine)
    finally:
        wrist.close()
    wrist.close()                                      # idempotent
    assert wrist.poll(0.0) is None
