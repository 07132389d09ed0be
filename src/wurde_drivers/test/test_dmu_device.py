"""The DMU driver against the DMU emulator over a real pty and real pyserial."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator

import pytest

from wurde_drivers.dmu import codec
from wurde_drivers.dmu.device import DmuDriver, RawSample
from wurde_drivers.dmu.emulator import DmuEmulator, constant_rate
from wurde_drivers.errors import DeviceTimeout
from wurde_drivers.ports.serial_link import SerialLink

ROLL, PITCH, RATE_Z = 0.1, 0.2, 0.5


@pytest.fixture
def emulator() -> Iterator[DmuEmulator]:
    with DmuEmulator(motion_source=constant_rate(RATE_Z, roll=ROLL, pitch=PITCH)) as device:
        yield device
    assert device.error is None


def make_driver(emulator: DmuEmulator, **options: object) -> DmuDriver:
    return DmuDriver(SerialLink(emulator.path, codec.DEFAULT_BAUDRATE, retry_s=0.05), **options)


def collect(driver: DmuDriver, count: int, within: float = 20.0) -> list[RawSample]:
    deadline = time.monotonic() + within
    samples: list[RawSample] = []
    while len(samples) < count and time.monotonic() < deadline:
        samples += driver.poll(0.1)
    assert len(samples) >= count, f'only {len(samples)} samples in {within} s'
    return samples


def test_connect_streams_samples_in_the_robot_frame(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator)
    try:
        driver.connect()
        sample = collect(driver, 10)[-1]
        assert list(emulator.commands)[:4] == [b'P', b'R', b'a', b'C']
        # sensor frame is z down; the robot frame is z up, y left (Pluto 8.2)
        assert sample.roll == pytest.approx(ROLL, abs=1e-3)
        assert sample.pitch == pytest.approx(-PITCH, abs=1e-3)
        assert sample.rate_z == pytest.approx(-RATE_Z, abs=1e-3)
        assert sample.accel_z == pytest.approx(9.80665 * math.cos(ROLL) * math.cos(PITCH),
                                               abs=2e-2)
        assert sample.accel_z > 0 and sample.temperature == pytest.approx(25.0, abs=0.1)
        assert driver.stats.telegrams >= 10 and driver.stats.bad_crc == 0
        assert driver.silent_for < 0.5
    finally:
        driver.close()


def test_packets_read_in_one_burst_are_stamped_by_the_units_time_word(emulator: DmuEmulator) -> None:
    """A loaded machine reads many packets at once: they are stamped apart by the unit's own
    time word (the emulator's period), not all with the time of the read."""
    driver = make_driver(emulator)
    try:
        driver.connect()
        collect(driver, 5)
        time.sleep(0.3)                     # let packets pile up in the pty: one burst read
        burst = driver.poll(0.1)
        assert len(burst) >= 10
        gaps = [b.stamp - a.stamp for a, b in zip(burst, burst[1:])]
        assert all(0.0 < gap < 3 * emulator.period for gap in gaps), gaps      # the emulator's send times
        assert sum(gaps) / len(gaps) == pytest.approx(emulator.period, abs=1e-3)
        later = collect(driver, 1)
        assert later[0].stamp >= burst[-1].stamp
    finally:
        driver.close()


def test_scaled_mode_has_rates_but_no_angles(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator, mode=codec.DmuMode.SCALED)
    try:
        driver.connect()
        sample = collect(driver, 3)[-1]
        assert sample.roll is None and sample.pitch is None
        assert sample.rate_z == pytest.approx(-RATE_Z, abs=1e-3)
        assert emulator.mode is codec.DmuMode.SCALED
    finally:
        driver.close()


def test_packet_rate_never_exceeds_what_the_baud_rate_carries() -> None:
    with DmuEmulator(rate_hz=10000.0) as fast, DmuEmulator(rate_hz=50.0) as slow:
        assert fast.period == pytest.approx(22 * 10 / 38400)
        assert slow.period == pytest.approx(1 / 50)


def test_bad_checksums_are_dropped_and_counted(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator)
    try:
        driver.connect()
        collect(driver, 2)
        emulator.inject_bad_checksums(3)
        deadline = time.monotonic() + 20.0
        while driver.stats.bad_crc < 3 and time.monotonic() < deadline:
            driver.poll(0.1)
        assert driver.stats.bad_crc >= 3
        collect(driver, 5)                                 # and data flows on
    finally:
        driver.close()


def test_garbage_between_packets_is_skipped(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator)
    try:
        driver.connect()
        collect(driver, 2)
        before = driver.stats.telegrams
        emulator.inject_garbage(bytes(range(0x20, 0x60)))   # no 0xFF: cannot fake a header
        deadline = time.monotonic() + 20.0
        while driver.stats.bytes_skipped < 0x40 and time.monotonic() < deadline:
            driver.poll(0.1)
        assert driver.stats.bytes_skipped >= 0x40
        collect(driver, 5)
        assert driver.stats.telegrams >= before + 5
    finally:
        driver.close()


def test_silent_unit_times_out_and_is_rearmed(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator, rearm_after=0.2)
    try:
        driver.connect()
        collect(driver, 2)
        emulator.silent.set()
        assert emulator.settle()                            # nothing more is coming
        deadline = time.monotonic() + 20.0
        while driver.poll(0.05) and time.monotonic() < deadline:
            pass                                            # drain what was in flight
        started = time.monotonic()
        assert driver.poll(0.3) == []
        # poll kept its deadline (the upper bound allows for a loaded machine's scheduling)
        assert 0.25 <= time.monotonic() - started < 0.3 + 1.0
        deadline = time.monotonic() + 20.0
        while driver.rearms < 1 and time.monotonic() < deadline:
            driver.poll(0.1)
        assert driver.rearms >= 1 and driver.silent_for >= 0.2
        assert driver.stats.timeouts >= 1
        emulator.silent.clear()
        collect(driver, 3)
        assert driver.silent_for < 0.5
    finally:
        driver.close()


def test_unplugged_unit_returns_power_cycled_and_data_flows_again(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator, rearm_after=0.2)
    try:
        driver.connect()
        collect(driver, 2)
        emulator.unplug()
        deadline = time.monotonic() + 20.0
        while driver.silent_for < 0.5 and time.monotonic() < deadline:
            driver.poll(0.1)
        assert driver.silent_for >= 0.5
        emulator.replug()                                   # back in polled mode
        assert not emulator.continuous
        collect(driver, 3)                                  # the driver re-armed it
        assert driver.rearms >= 1 and emulator.continuous
    finally:
        driver.close()


def test_connect_to_a_silent_unit_raises_device_timeout(emulator: DmuEmulator) -> None:
    emulator.silent.set()
    driver = make_driver(emulator)
    started = time.monotonic()
    try:
        with pytest.raises(DeviceTimeout):
            driver.connect(timeout=0.5)
        assert time.monotonic() - started < 0.5 + 1.5      # (slack for a loaded machine)
    finally:
        driver.close()


def test_unit_at_another_baud_rate_does_not_answer(emulator: DmuEmulator) -> None:
    driver = DmuDriver(SerialLink(emulator.path, 9600))
    try:
        with pytest.raises(DeviceTimeout):
            driver.connect(timeout=0.5)
    finally:
        driver.close()


def test_vanished_port_is_counted_not_raised() -> None:
    emulator = DmuEmulator().start()
    driver = make_driver(emulator)
    try:
        driver.connect()
        collect(driver, 2)
        emulator.stop()
        deadline = time.monotonic() + 20.0
        while driver.stats.disconnects < 1 and time.monotonic() < deadline:
            assert isinstance(driver.poll(0.1), list)
        assert driver.stats.disconnects >= 1
    finally:
        driver.close()
        emulator.stop()


def test_polled_commands_over_a_raw_link(emulator: DmuEmulator) -> None:
    link = SerialLink(emulator.path, codec.DEFAULT_BAUDRATE)
    with link:
        def read_exactly(count: int) -> bytes:
            data, deadline = b'', time.monotonic() + 20.0
            while len(data) < count and time.monotonic() < deadline:
                data += link.read(0.1)
            return data

        link.write(codec.CMD_GET)
        packet = codec.decode_packet(read_exactly(22), codec.DmuMode.ANGLE)
        assert packet.rate_z == pytest.approx(RATE_Z, abs=1e-3)     # sensor frame: z down
        link.write(codec.CMD_SERIAL)
        assert codec.decode_serial_number(read_exactly(6)) == emulator.serial_number
        link.write(codec.CMD_VERSION)
        assert read_exactly(len(emulator.version)).decode() == emulator.version
        link.write(codec.CMD_PING)
        assert read_exactly(1) == codec.REPLY_PING


def test_explicit_reconnect_restarts_the_stream(emulator: DmuEmulator) -> None:
    driver = make_driver(emulator, rearm_after=60.0)        # no automatic re-arm here
    try:
        driver.connect()
        collect(driver, 2)
        emulator.unplug()
        emulator.replug()                                   # power cycled: polled, silent
        assert emulator.settle()                            # nothing more is coming
        deadline = time.monotonic() + 20.0
        while driver.poll(0.05) and time.monotonic() < deadline:
            pass
        assert driver.poll(0.2) == []
        driver.reconnect()
        collect(driver, 3)
        assert driver.rearms == 0 and list(emulator.commands).count(b'R') == 2
    finally:
        driver.close()
