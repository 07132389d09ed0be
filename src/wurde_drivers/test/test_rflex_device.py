"""The rFLEX driver against the rFLEX emulator over a real pty and real pyserial."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator

import pytest

from wurde_drivers.errors import DeviceError, DeviceTimeout
from wurde_drivers.ports.serial_link import SerialLink
from wurde_drivers.rflex import codec as rflex
from wurde_drivers.rflex.config import RFlexDevice
from wurde_drivers.rflex.device import RFlexDriver
from wurde_drivers.rflex.emulator import RFlexEmulator
from wurde_drivers.rflex.robots import B21R

CONNECT_SEQUENCE = [rflex.set_defaults(), rflex.system_report_req(100000, 3),
                    rflex.sonar_run(True), rflex.dio_reports_req(100000)]


@pytest.fixture
def emulator() -> Iterator[RFlexEmulator]:
    with RFlexEmulator(B21R) as emu:
        yield emu
        assert emu.error is None


def driver_for(emu: RFlexEmulator, **options: object) -> RFlexDriver:
    options = {'brake_reset': True, 'command_timeout': None, 'silence_s': 0.3,
               'resend_s': 0.3, **options}
    return RFlexDriver(SerialLink(emu.path, 115200), B21R, **options)  # type: ignore[arg-type]


@pytest.fixture
def driver(emulator: RFlexEmulator) -> Iterator[RFlexDriver]:
    drv = driver_for(emulator)
    drv.connect(timeout=2.0)
    try:
        yield drv
    finally:
        drv.close()


def poll_until(drv: RFlexDriver, condition: Callable[[], bool], timeout: float = 20.0,
               sink: list | None = None) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, 'condition not met before the deadline'
        reports = drv.poll(0.05)
        if sink is not None:
            sink += reports


def test_connect_sequence_and_status(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    poll_until(driver, lambda: len(emulator.commands()) >= 6)
    assert emulator.commands()[:6] == CONNECT_SEQUENCE + [rflex.brake_release(),
                                                          rflex.sys_status_poll()]
    assert emulator.baudrate == 115200
    poll_until(driver, lambda: driver.state.brake is False and driver.state.odometry_ready)
    assert driver.state.voltage == pytest.approx(26.0)
    assert emulator.report_period_s == pytest.approx(0.1)
    assert emulator.sonar_on and emulator.dio_period == 100000


def test_brake_is_released_only_when_allowed(emulator: RFlexEmulator) -> None:
    drv = driver_for(emulator, brake_reset=False)
    drv.connect()
    try:
        poll_until(drv, lambda: drv.state.brake is True and len(emulator.commands()) >= 5)
        assert emulator.commands()[:5] == CONNECT_SEQUENCE + [rflex.sys_status_poll()]
        drv.set_velocity(0.5, 0.0, 10.0)
        reports: list = []
        poll_until(drv, lambda: sum(isinstance(r, rflex.MotorReport) for r in reports) >= 8,
                   sink=reports)
        assert drv.state.distance == 0.0 and emulator.distance_m() == 0.0   # the brake holds
        with pytest.raises(DeviceError):
            drv.brake(False)
        assert drv.brake(True)
    finally:
        drv.close()
    assert rflex.brake_release() not in emulator.commands()


def test_brake_command_when_allowed(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    poll_until(driver, lambda: driver.state.brake is False)
    driver.brake(True)
    poll_until(driver, lambda: driver.state.brake is True)
    assert emulator.brake


def timed_poses(drv: RFlexDriver, count: int) -> list[tuple[float, float, float, float]]:
    """(base time s, x, y, theta) at bearing reports, i.e. completed odometry steps.

    ``poll`` returns every report it decoded, and the state after the last of them: on a loaded
    machine a batch can hold two report cycles, so only a batch's last bearing report is paired
    with the state (a distance report after it does not move the pose until the next bearing).
    """
    poses: list[tuple[float, float, float, float]] = []
    deadline = time.monotonic() + 20.0
    while len(poses) < count:
        assert time.monotonic() < deadline
        bearings = [r for r in drv.poll(0.05) if isinstance(r, rflex.MotorReport) and r.axis == 1]
        if bearings:
            state = drv.state
            poses.append((bearings[-1].timestamp / 1000.0, state.x, state.y, state.theta))
    return poses


@pytest.mark.parametrize('stuff', [False, True], ids=['esc-free', 'stuffed'])
def test_straight_motion_follows_x_equals_v_t(stuff: bool) -> None:
    with RFlexEmulator(B21R, stuff_esc=stuff) as emu:
        drv = driver_for(emu)
        drv.connect()
        try:
            poll_until(drv, lambda: drv.state.odometry_ready)
            drv.set_velocity(0.6, 0.0, 20.0)
            poll_until(drv, lambda: drv.state.tv == pytest.approx(0.6))
            poses = timed_poses(drv, 6)           # crosses the 0x1B00 counts at 6.7 cm
            for stamp, x, y, theta in poses:
                assert x - 0.6 * stamp == pytest.approx(poses[0][1] - 0.6 * poses[0][0], abs=3e-3)
                assert (y, theta) == (0.0, 0.0)
            assert drv.state.x == pytest.approx(emu.distance_m(), abs=0.6 * 0.3)
            assert drv.stats.bad_crc == 0 and drv.stats.bytes_skipped == 0
        finally:
            drv.close()
        assert emu.error is None


def test_arc_follows_the_circle(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    v, w = 0.5, -1.25                     # equal ramp times keep the curvature constant
    poll_until(driver, lambda: driver.state.odometry_ready)
    driver.set_velocity(v, w, 5.0, 12.5)
    poses = timed_poses(driver, 9)
    radius = v / abs(w)
    for _, x, y, theta in poses:
        assert x == pytest.approx(radius * math.sin(-theta), abs=5e-3)
        assert y == pytest.approx(-radius * (1.0 - math.cos(theta)), abs=5e-3)
    (t0, *_, th0), (t1, *_, th1) = poses[-2], poses[-1]
    assert (th1 - th0) / (t1 - t0) == pytest.approx(w, rel=0.02)
    assert driver.state.rv == pytest.approx(w, abs=1e-3)
    assert driver.state.tv == pytest.approx(v, abs=1e-3)


def test_odometry_survives_the_32_bit_wrap(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    poll_until(driver, lambda: driver.state.odometry_ready)
    emulator.set_counter(0, (1 << 31) - 5000)
    emulator.set_counter(1, -(1 << 31) + 3000)
    poll_until(driver, lambda: driver.odometry_resets == 2)    # a jump is re-baselined
    assert driver.state.distance == 0.0
    start = emulator.distance_m()
    driver.set_velocity(0.5, -0.5, 50.0, 50.0)
    poll_until(driver, lambda: driver.state.distance > 0.2)
    assert emulator.distance_m() * B21R.units_per_m > 1 << 31      # the counters wrapped
    assert driver.state.distance == pytest.approx(emulator.distance_m() - start, abs=0.5 * 0.3)
    assert driver.state.theta < -0.15
    assert driver.odometry_resets == 2


def test_reports_come_at_the_requested_period(driver: RFlexDriver) -> None:
    stamps: dict[int, list[int]] = {0: [], 1: []}
    deadline = time.monotonic() + 3.0
    while len(stamps[1]) < 8:
        assert time.monotonic() < deadline
        for report in driver.poll(0.05):
            if isinstance(report, rflex.MotorReport):
                stamps[report.axis].append(report.timestamp)
    one = stamps[1]
    assert (one[-1] - one[0]) / (len(one) - 1) == pytest.approx(100, abs=10)
    assert set(one) <= set(stamps[0]) | {one[0]}     # one report per axis each period


def test_sonar_ranges(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    emulator.sonar_ranges = lambda: [1.0] * 24 + [math.inf] * 23 + [2.5]
    poll_until(driver, lambda: driver.state.sonar[0] == pytest.approx(1.0, abs=1e-3)
               and driver.state.sonar[47] == pytest.approx(2.5, abs=1e-3))
    assert math.isinf(driver.state.sonar[30])
    assert len(driver.state.sonar) == 48


def test_bumpers(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    assert not driver.state.bumped
    emulator.set_bumper(0x4B, 0b0101)
    poll_until(driver, lambda: driver.state.bumped)
    assert driver.state.bumpers == {0x4B: 0b0101}
    emulator.set_bumper(0x4B, 0)
    poll_until(driver, lambda: not driver.state.bumped)


def test_bad_crc_and_garbage_are_counted_and_data_flows(emulator: RFlexEmulator,
                                                       driver: RFlexDriver) -> None:
    poll_until(driver, lambda: driver.state.odometry_ready)
    emulator.corrupt_next(3)
    poll_until(driver, lambda: driver.stats.bad_crc >= 3)
    emulator.garbage = b'\x00\xffjunk\x1b\x1b\x00\x03'
    driver.set_velocity(0.5, 0.0, 20.0)
    poll_until(driver, lambda: driver.stats.bytes_skipped >= 40 and driver.state.x > 0.2)
    assert driver.state.x == pytest.approx(emulator.distance_m(), abs=0.5 * 0.3)
    assert driver.stats.bad_crc == 3 and driver.odometry_resets == 0


def test_silence_is_reported_and_recovered(emulator: RFlexEmulator, driver: RFlexDriver) -> None:
    poll_until(driver, lambda: driver.state.odometry_ready)
    emulator.silent.set()
    assert emulator.settle()                               # nothing more is coming
    poll_until(driver, lambda: driver.silent)
    assert driver.silent_for() > 0.3 and driver.stats.timeouts == 1
    start = time.monotonic()
    assert driver.poll(0.2) == []
    assert time.monotonic() - start < 0.2 + 1.0            # poll keeps to its budget (+ load)
    emulator.silent.clear()
    poll_until(driver, lambda: not driver.silent)


def test_unplug_and_replug_with_power_cycle(emulator: RFlexEmulator,
                                            driver: RFlexDriver) -> None:
    driver.set_velocity(0.5, 0.5, 20.0, 20.0)
    poll_until(driver, lambda: driver.state.distance > 0.2)
    driver.stop()
    poll_until(driver, lambda: driver.state.tv == 0.0 and driver.state.rv == 0.0)
    pose = (driver.state.x, driver.state.y, driver.state.theta)
    emulator.unplug()
    poll_until(driver, lambda: driver.silent)
    emulator.replug(power_cycle=True)                      # the base forgot every request
    assert emulator.report_period_s == 0.0
    poll_until(driver, lambda: emulator.report_period_s > 0 and driver.state.odometry_ready
               and not driver.silent)
    assert driver.resyncs >= 1 and driver.odometry_resets == 0
    assert (driver.state.x, driver.state.y, driver.state.theta) == pytest.approx(pose, abs=1e-3)
    assert emulator.commands().count(rflex.system_report_req(100000, 3)) >= 2


def test_a_base_that_forgot_its_reports_is_told_again(emulator: RFlexEmulator,
                                                     driver: RFlexDriver) -> None:
    """A base power-cycled too quickly for the driver to find it silent may well answer the
    SYS_STATUS polls, but sends no odometry: the start-up sequence must go out again (a loaded
    run of the unplug test above hung there)."""
    poll_until(driver, lambda: driver.state.odometry_ready)
    resyncs, requests = driver.resyncs, emulator.commands().count(rflex.system_report_req(100000, 3))
    emulator.replug(power_cycle=True)                      # rebooted: every request forgotten
    assert emulator.report_period_s == 0.0
    poll_until(driver, lambda: emulator.report_period_s > 0 and driver.state.odometry_ready)
    assert driver.resyncs > resyncs
    assert emulator.commands().count(rflex.system_report_req(100000, 3)) > requests


def test_link_reopened_after_the_port_vanished(emulator: RFlexEmulator,
                                               driver: RFlexDriver) -> None:
    poll_until(driver, lambda: driver.state.odometry_ready)
    driver.link.close()                        # what SerialLink does when the device vanishes
    poll_until(driver, lambda: driver.stats.reconnects == 1 and driver.resyncs == 1)
    poll_until(driver, lambda: emulator.commands().count(rflex.set_defaults()) == 2)
    before = driver.stats.telegrams
    poll_until(driver, lambda: driver.stats.telegrams > before + 4)
    assert driver.stats.reconnects == 1 and driver.stats.telegrams > before + 4


def test_command_timeout_stops_the_base(emulator: RFlexEmulator) -> None:
    drv = driver_for(emulator, command_timeout=0.3)
    drv.connect()
    try:
        drv.set_velocity(0.4, 0.0, 20.0)
        poll_until(drv, lambda: drv.state.tv == pytest.approx(0.4))
        poll_until(drv, lambda: drv.state.tv == 0.0)
        assert emulator.velocities() == (0.0, 0.0)
        # The last motion commands are the stop pair (the driver's other packets, e.g. its
        # report requests, may come after them on a loaded machine).
        stop = [rflex.esc_free_set_dir(0, 0, 72100, 30000, 1), rflex.esc_free_set_dir(1, 0, 100000, 35000, 1)]
        moves = [c for c in emulator.commands() if (c.port, c.opcode) == (stop[0].port, stop[0].opcode)]
        assert moves[-2:] == stop
    finally:
        drv.close()


def test_connect_failures(emulator: RFlexEmulator) -> None:
    with pytest.raises(DeviceError):
        RFlexDriver(SerialLink('/dev/nonexistent-rflex', 115200)).connect()
    emulator.silent.set()
    drv = driver_for(emulator)
    start = time.monotonic()
    with pytest.raises(DeviceTimeout):
        drv.connect(timeout=0.3)
    assert time.monotonic() - start < 0.3 + 1.5           # (slack for a loaded machine)
    drv.close()
    assert not drv.link.is_open


def test_close_is_idempotent_and_switches_reports_off(emulator: RFlexEmulator) -> None:
    drv = RFlexDriver.from_config(RFlexDevice(emulator.path, 'base', 'B21r', brake_reset=False))
    assert drv.robot is B21R and drv.command_timeout == 1.0 and not drv.brake_reset
    drv.connect()
    drv.close()
    drv.close()
    deadline = time.monotonic() + 2.0
    while (emulator.report_period_s or emulator.sonar_on
           or rflex.dio_reports_req(0) not in emulator.commands()):   # the last of close's writes
        assert time.monotonic() < deadline
        time.sleep(0.01)
    assert rflex.dio_reports_req(0) in emulator.commands()
    assert not drv.link.is_open
    with pytest.raises(DeviceError):
        drv.poll(0.1)
    assert drv.set_velocity(0.1, 0.0) is False and not drv.link.is_open


def test_a_timed_out_connect_keeps_trying(emulator: RFlexEmulator) -> None:
    emulator.unplug()                            # the start-up sequence is lost
    drv = driver_for(emulator)
    try:
        with pytest.raises(DeviceTimeout):
            drv.connect(timeout=0.2)
        emulator.replug(power_cycle=False)
        poll_until(drv, lambda: drv.state.odometry_ready)     # base answered a re-sent request
        assert drv.resyncs >= 1
        assert emulator.commands()[:2] == CONNECT_SEQUENCE[:2]
    finally:
        drv.close()
