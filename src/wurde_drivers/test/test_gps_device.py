"""The NMEA GPS reader against the emulated receiver over a real pty and pyserial."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterator

import pytest

from wurde_drivers.gps.device import BAUDRATE, Fix, GpsReceiver
from wurde_drivers.gps.emulator import GpsEmulator, GpsSample
from wurde_drivers.gps.geo import LocalFrame
from wurde_drivers.gps.quality import meets
from wurde_drivers.ports.serial_link import SerialLink

ORIGIN = (59.3293, 18.0686)          # a good fix's position, the frame's origin
RATE = 20.0                          # Hz: quick tests


def walking_north(elapsed: float) -> GpsSample:
    """2 m/s due north from ORIGIN (1 deg of latitude is about 111.2 km here)."""
    return GpsSample(ORIGIN[0] + 2.0 * elapsed / 111_200.0, ORIGIN[1], 30.0, 2.0, 0.0)


def collect(gps: GpsReceiver, count: int, timeout: float = 20.0) -> list[Fix]:
    deadline = time.monotonic() + timeout
    fixes: list[Fix] = []
    while len(fixes) < count:
        remaining = deadline - time.monotonic()
        assert remaining > 0, f'only {len(fixes)} of {count} fixes before the deadline'
        fixes.extend(gps.poll(remaining))
    return fixes


def polled(gps: GpsReceiver, condition: Callable[[], bool]) -> Callable[[], bool]:
    """A condition that first lets ``gps`` read for a moment."""
    def check() -> bool:
        gps.poll(0.05)
        return condition()
    return check


def wait_for(condition: Callable[[], bool], timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, 'condition not met before the deadline'
        time.sleep(0.01)


@pytest.fixture
def receiver() -> Iterator[GpsEmulator]:
    with GpsEmulator(walking_north, rate_hz=RATE, quality=2, satellites=8) as emulator:
        yield emulator
    assert emulator.error is None


@pytest.fixture
def gps(receiver: GpsEmulator) -> Iterator[GpsReceiver]:
    reader = GpsReceiver(SerialLink(receiver.path, BAUDRATE, retry_s=0.05))
    try:
        yield reader
    finally:
        reader.close()


def test_fixes_carry_the_gga_fields_and_frame_position(receiver: GpsEmulator,
                                                      gps: GpsReceiver) -> None:
    fixes = collect(gps, 6)
    first = fixes[0]
    assert first.good and (first.satellites, first.quality) == (8, 2)
    assert first.hdop == pytest.approx(0.9) and first.altitude == pytest.approx(30.0)
    assert (first.x, first.y) == (0.0, 0.0)                 # the first good fix is the origin
    assert gps.frame is not None and gps.frame.latitude == pytest.approx(first.latitude)
    last = fixes[-1]
    # walking north at 2 m/s, 20 Hz: y grows by about 0.1 m per fix, x stays 0
    assert last.y == pytest.approx(2.0 * (last.fix_time - first.fix_time), abs=0.05)
    assert abs(last.x) < 0.05
    assert last.speed == pytest.approx(2.0, abs=0.002) and last.course == pytest.approx(0.0)
    assert last.date is not None
    assert receiver.baudrate == BAUDRATE
    assert gps.stats.telegrams >= 11 and gps.counters['bad_checksum'] == 0


def test_fixes_read_together_keep_their_own_times(receiver: GpsEmulator, gps: GpsReceiver) -> None:
    """A reader late to read (a loaded machine) gets several sentences in one read: each fix is
    stamped when its last byte arrived, older by the wire time of what came after it, not all
    with the read's time (two fixes with one stamp reached a test once)."""
    collect(gps, 1)                                            # the port is open and reading
    sent = receiver.sentences_sent
    wait_for(lambda: receiver.sentences_sent >= sent + 10)     # a backlog of five fixes
    fixes = gps.poll(0.2)
    assert len(fixes) >= 3
    stamps = [fix.stamp for fix in fixes]
    assert all(b > a for a, b in zip(stamps, stamps[1:])), stamps
    assert stamps[-1] <= time.monotonic()


def test_a_given_origin_is_used(receiver: GpsEmulator) -> None:
    origin = (ORIGIN[0] - 0.001, ORIGIN[1] + 0.001)
    gps = GpsReceiver(SerialLink(receiver.path, BAUDRATE), origin=origin)
    try:
        fix = collect(gps, 1)[0]
        expected = LocalFrame(*origin).to_xy(fix.latitude, fix.longitude)
        assert (fix.x, fix.y) == pytest.approx(expected)
        assert fix.y == pytest.approx(111.2, abs=1.0) and fix.x == pytest.approx(-56.9, abs=1.0)
    finally:
        gps.close()


def test_good_follows_the_thresholds(receiver: GpsEmulator, gps: GpsReceiver) -> None:
    receiver.satellites = 5                     # Pluto: more than 5 needed
    wait_for(lambda: any(f.satellites == 5 for f in gps.poll(0.5)))
    fix = collect(gps, 1)[0]
    assert not fix.good and math.isnan(fix.x)   # no good fix yet: no origin
    receiver.satellites, receiver.quality = 9, 1
    wait_for(lambda: any(f.quality == 1 for f in gps.poll(0.5)))
    assert not collect(gps, 1)[0].good
    gps.min_quality = 1
    assert collect(gps, 1)[0].good
    assert gps.frame is not None


def test_the_quality_rank_is_accuracy_not_number() -> None:
    """Pluto 8.4's "quality 2" means DGPS or better: RTK (5 float, 4 fixed) is better, while
    6 dead reckoning, 7 manual and 8 simulation measure nothing however large they are."""
    assert [q for q in range(10) if meets(q, 2)] == [2, 4, 5]
    assert [q for q in range(10) if meets(q, 1)] == [1, 2, 3, 4, 5]
    assert [q for q in range(10) if meets(q, 0)] == [1, 2, 3, 4, 5]
    assert [q for q in range(10) if meets(q, 4)] == [4]
    assert [q for q in range(10) if meets(q, 5)] == [4, 5]
    for minimum in (6, 7, 8, 9, -1):
        with pytest.raises(ValueError):
            meets(2, minimum)
    with pytest.raises(ValueError):
        GpsReceiver(SerialLink('loop://', BAUDRATE), min_quality=6)


@pytest.mark.parametrize(('quality', 'good'), [(6, False), (7, False), (8, False), (1, False),
                                                (2, True), (5, True), (4, True)])
def test_dead_reckoning_is_never_a_good_fix_and_rtk_is(quality: int, good: bool) -> None:
    with GpsEmulator(walking_north, rate_hz=RATE, quality=quality, satellites=9) as receiver:
        gps = GpsReceiver(SerialLink(receiver.path, BAUDRATE))
        try:
            fixes = collect(gps, 2)
        finally:
            gps.close()
    assert receiver.error is None
    assert all(f.quality == quality and f.good is good for f in fixes)
    assert (gps.frame is not None) is good      # only a good fix may become the grid's origin
    assert gps.fixes == len(fixes) and gps.good_fixes == (len(fixes) if good else 0)


def test_no_fix_sentences_give_nan_positions(receiver: GpsEmulator, gps: GpsReceiver) -> None:
    receiver.quality = 0
    wait_for(lambda: any(f.quality == 0 for f in gps.poll(0.5)))
    fix = collect(gps, 1)[0]
    assert math.isnan(fix.latitude) and math.isnan(fix.x) and not fix.good


def test_bad_and_missing_checksums_are_dropped_and_counted(receiver: GpsEmulator,
                                                          gps: GpsReceiver) -> None:
    collect(gps, 1)
    receiver.corrupt_next(2)
    wait_for(polled(gps, lambda: gps.counters['bad_checksum'] >= 2))
    receiver.strip_checksum_next(1)
    wait_for(polled(gps, lambda: gps.counters['no_checksum'] >= 1))
    assert gps.stats.bad_crc >= 3
    assert collect(gps, 2)[-1].good


def test_garbage_between_sentences_is_skipped(receiver: GpsEmulator, gps: GpsReceiver) -> None:
    collect(gps, 1)
    skipped = gps.stats.bytes_skipped
    receiver.inject_garbage()
    receiver.inject_garbage(b'\xff' * 300)      # a runaway line, ended by the next sentence's \n
    fixes = collect(gps, 3)
    assert all(f.good for f in fixes)
    assert gps.stats.bytes_skipped >= skipped + 300


def test_a_silent_receiver_is_noticed_within_the_deadline(receiver: GpsEmulator,
                                                         gps: GpsReceiver) -> None:
    collect(gps, 1)
    receiver.silent.set()
    assert receiver.settle()                    # nothing more is coming
    wait_for(lambda: gps.poll(0.1) == [])       # what was on its way is read; now quiet
    start = time.monotonic()
    assert gps.poll(0.2) == []
    assert 0.19 <= time.monotonic() - start < 0.2 + 1.0   # (slack for a loaded machine)
    assert gps.silent_for() >= 0.2
    receiver.silent.clear()
    collect(gps, 1)
    assert gps.silent_for() < 0.5


def test_an_unplugged_receiver_comes_back(receiver: GpsEmulator, gps: GpsReceiver) -> None:
    collect(gps, 1)
    receiver.unplugged.set()
    wait_for(lambda: gps.poll(0.05) == [] and gps.silent_for() > 0.3)
    receiver.unplugged.clear()
    assert collect(gps, 2)[-1].good


def test_a_vanished_port_is_reopened() -> None:
    first = GpsEmulator(walking_north, rate_hz=RATE, quality=2).start()
    link = SerialLink(first.path, BAUDRATE, retry_s=0.05)
    gps = GpsReceiver(link)
    try:
        collect(gps, 1)
        first.stop()                              # the device node disappears
        wait_for(lambda: gps.poll(0.05) == [] and link.stats.disconnects >= 1)
        with GpsEmulator(walking_north, rate_hz=RATE, quality=2) as second:
            link.url = second.path                # ... and comes back (udev may rename it)
            fixes = collect(gps, 2)
            assert fixes[-1].good and link.stats.reconnects >= 2
    finally:
        gps.close()
        first.stop()


def test_a_long_read_picks_up_a_device_that_comes_back_meanwhile(tmp_path) -> None:
    """A read of 20 s on a port that is not there retries every retry_s and returns the device's
    bytes once it appears (it used to sleep out the whole timeout)."""
    alias = tmp_path / 'gps0'                       # a udev-style name, not there yet
    link = SerialLink(str(alias), BAUDRATE, retry_s=0.05)
    devices: list[GpsEmulator] = []

    def plug_in() -> None:
        deadline = time.monotonic() + 20.0
        while link.stats.open_failures < 2 and time.monotonic() < deadline:   # the read is retrying
            time.sleep(0.01)
        device = GpsEmulator(walking_north, rate_hz=RATE, quality=2).start()
        devices.append(device)
        alias.symlink_to(device.path)

    helper = threading.Thread(target=plug_in)
    helper.start()
    try:
        data = link.read(20.0)
        helper.join()
        assert data and link.stats.open_failures >= 2 and link.stats.reconnects == 1
    finally:
        helper.join()
        link.close()
        for device in devices:
            device.stop()


def test_a_wrong_line_speed_gives_no_fixes_until_corrected() -> None:
    with GpsEmulator(walking_north, rate_hz=RATE, quality=2, baudrate=38400) as receiver:
        link = SerialLink(receiver.path, BAUDRATE)
        gps = GpsReceiver(link)
        try:
            # Read a few sentence pairs' worth of wrong-speed garbage (no line ends, so one
            # runaway line): not one fix may come of any of it.
            deadline = time.monotonic() + 20.0
            while gps.stats.bytes_in < 600:
                assert time.monotonic() < deadline, 'no garbage read at the wrong speed'
                assert gps.poll(0.1) == []
            assert gps.counters['too_long'] >= 1 and gps.fixes == 0
            link.set_baudrate(38400)
            assert collect(gps, 1)[0].good
        finally:
            gps.close()


def test_sentences_and_constructor_checks() -> None:
    receiver = GpsEmulator(lambda t: (10.5, -20.25, 5.0, 1.0, -90.0), quality=1)
    try:
        gga, rmc = receiver.sentences(0.0)
        assert gga.startswith(b'$GPGGA,') and rmc.startswith(b'$GPRMC,')
        assert rmc.count(b',') == 11                # classic RMC: 12 fields with the address
        assert b',1030.00000,N,02015.00000,W,' in gga
        assert b',270.0,' in rmc                   # course -90 written as 270
    finally:
        receiver.stop()
    with pytest.raises(ValueError):
        GpsEmulator(baudrate=115200)
