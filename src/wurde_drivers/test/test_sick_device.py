"""SICK device layer against the emulator over a real pty and real pyserial (no mocks)."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator

import pytest
import serial

from wurde_drivers.errors import DeviceError, DeviceTimeout
from wurde_drivers.ports.pty import PtyDevice
from wurde_drivers.sick import codec as sick
from wurde_drivers.sick.device import LaserState, SickLaser
from wurde_drivers.sick.emulator import SickEmulator

INF_BEAM, NAN_BEAM = 5, 7
#: How long the laser may take to answer a request: sicktoolbox's
#: DEFAULT_SICK_LMS_2XX_SICK_MESSAGE_TIMEOUT (1 s).  Every exchange the emulator must answer
#: gets this, never a tighter guess (a loaded machine can delay an answer by more than 0.1 s);
#: only requests that nobody will answer (a silent line, an unplugged or deaf device) get
#: NO_REPLY_S, whose length only sets the test's pace.
REPLY_S = 1.0
NO_REPLY_S = 0.05


def source(count: int, fov_deg: float) -> list[float]:
    """0.2 m .. 7.9 m along the scan (inside the mm range), one beam too far, one invalid."""
    ranges = [0.2 + 7.7 * i / count for i in range(count)]
    ranges[INF_BEAM], ranges[NAN_BEAM] = math.inf, math.nan
    return ranges


def collect(laser: SickLaser, wanted: int, within: float) -> list:
    """Poll until ``wanted`` scans arrived or ``within`` seconds passed."""
    scans: list = []
    deadline = time.monotonic() + within
    while len(scans) < wanted and time.monotonic() < deadline:
        scans += laser.poll(min(0.2, max(deadline - time.monotonic(), 0.0)))
    return scans


def wait_silent(laser: SickLaser, seconds: float, within: float) -> None:
    deadline = time.monotonic() + within
    while laser.silent_for() < seconds:
        assert time.monotonic() < deadline, 'the laser never went silent'
        laser.poll(0.05)


def assert_matches_source(scan, units: str, invert: bool = False) -> None:
    expected = source(scan.count, 180.0)
    if invert:
        expected.reverse()
    step = 0.01 if units == 'cm' else 0.001
    for index, (got, want) in enumerate(zip(scan.ranges, expected, strict=True)):
        if math.isnan(want):
            assert math.isnan(got), index
        elif math.isinf(want):
            assert got == math.inf, index
        else:
            assert abs(got - want) <= step / 2 + 1e-9, (index, got, want)


@pytest.fixture
def emulator() -> Iterator[SickEmulator]:
    with SickEmulator(scan_source=source, reset_s=0.2) as device:
        yield device
        assert device.error is None


@pytest.fixture
def laser(emulator: SickEmulator) -> Iterator[SickLaser]:
    device = SickLaser(emulator.path, baudrate=38400, resolution=1.0, units='cm',
                       reply_timeout=REPLY_S)
    try:
        device.connect()
        yield device
    finally:
        device.close()


@pytest.mark.parametrize(('baud', 'resolution', 'units'), [
    (38400, 0.5, 'cm'), (38400, 1.0, 'mm'), (500000, 0.5, 'mm'), (500000, 1.0, 'cm')])
def test_connect_from_9600_and_stream(emulator: SickEmulator, baud: int, resolution: float,
                                      units: str) -> None:
    assert emulator.device_baud == 9600
    laser = SickLaser(emulator.path, baudrate=baud, resolution=resolution, units=units,
                      reply_timeout=REPLY_S)
    try:
        laser.connect()
        assert laser.state is LaserState.STREAMING
        assert emulator.device_baud == baud == laser.baudrate
        assert emulator.config.units == units and laser.type_string.startswith('LMS200')
        scans = collect(laser, 2, within=3.0)
        assert len(scans) == 2
        count = 181 if resolution == 1.0 else 361
        for scan in scans:
            assert (scan.count, scan.units, len(scan.ranges)) == (count, units, count)
            assert_matches_source(scan, units)
            wire = (6 + 4 + 2 * count) * 10 / baud
            assert scan.arrival_time - scan.centre_time == pytest.approx(wire + 0.5 / 75, abs=1e-5)
        assert scans[0].angle_increment == pytest.approx(math.pi / (count - 1))
        assert laser.stats.bad_crc == 0 and laser.silent_for() < 1.0
    finally:
        laser.close()
        laser.close()  # idempotent
    assert laser.state is LaserState.CLOSED


def test_centre_time_at_38400_is_about_200_ms_early(emulator: SickEmulator) -> None:
    laser = SickLaser(emulator.path, reply_timeout=REPLY_S)  # Pluto 8.1: 38400, 361, cm
    try:
        laser.connect()
        (scan, *_) = collect(laser, 1, within=3.0)
        assert 0.19 < scan.arrival_time - scan.centre_time < 0.21
        assert laser.max_range == pytest.approx(81.82)
    finally:
        laser.close()


def test_invert_reverses_the_beams(emulator: SickEmulator) -> None:
    laser = SickLaser(emulator.path, resolution=1.0, invert=True, reply_timeout=REPLY_S)
    try:
        laser.connect()
        (scan, *_) = collect(laser, 1, within=3.0)
        assert_matches_source(scan, 'cm', invert=True)
        assert scan.raw[-1 - INF_BEAM] == 8183 and scan.ranges[-1 - INF_BEAM] == math.inf
    finally:
        laser.close()


def test_pls_connects_without_parity_on_a_pty() -> None:
    with SickEmulator(kind='PLS', scan_source=source) as emulator:
        laser = SickLaser(emulator.path, kind='PLS', parity=serial.PARITY_NONE,
                          reply_timeout=REPLY_S)
        try:
            laser.connect()
            (scan, *_) = collect(laser, 1, within=3.0)
            assert scan.count == 361 and laser.max_range == 50.0
            assert_matches_source(scan, 'cm')
            assert 0x3A not in emulator.commands and 0x3B not in emulator.commands
        finally:
            laser.close()


def test_bad_crc_is_dropped_counted_and_the_stream_continues(emulator: SickEmulator,
                                                            laser: SickLaser) -> None:
    assert collect(laser, 1, within=2.0)
    emulator.corrupt_next(3)
    scans = collect(laser, 3, within=3.0)
    assert len(scans) == 3
    assert laser.stats.bad_crc >= 3
    assert emulator.scans_sent >= laser.scans + 3  # the corrupted ones were sent, not delivered


def test_garbage_between_frames_loses_no_scan(emulator: SickEmulator, laser: SickLaser) -> None:
    assert collect(laser, 1, within=2.0)
    emulator.inject_garbage(b'\x55\x02\x80\x10\x00\xaa\x02', frames=4)
    skipped, scans = laser.stats.bytes_skipped, collect(laser, 6, within=3.0)
    assert len(scans) == 6
    assert laser.stats.bytes_skipped - skipped >= 4 * 7
    # A false start whose claimed length is complete fails its CRC: at most one per injection.
    assert laser.stats.bad_crc <= 4 and laser.bad_scans == 0


def test_silence_is_seen_within_a_deadline_and_poll_keeps_time(emulator: SickEmulator,
                                                               laser: SickLaser) -> None:
    assert collect(laser, 1, within=2.0)
    emulator.silent.set()
    assert emulator.settle()                    # nothing more is coming
    wait_silent(laser, 0.5, within=20.0)
    started = time.monotonic()
    assert laser.poll(0.1) == []
    assert time.monotonic() - started < 0.1 + 1.0      # (slack for a loaded machine)
    emulator.silent.clear()
    assert collect(laser, 1, within=2.0)
    assert laser.silent_for() < 0.5


def test_fatal_error_then_recover(emulator: SickEmulator, laser: SickLaser) -> None:
    assert collect(laser, 1, within=2.0)
    emulator.fatal_error()
    wait_silent(laser, 0.5, within=3.0)
    laser.recover(reset_timeout=3.0)
    assert laser.state is LaserState.STREAMING
    assert 0x10 in emulator.commands and not emulator.fatal
    assert emulator.device_baud == 38400
    scans = collect(laser, 2, within=3.0)
    assert len(scans) == 2
    assert_matches_source(scans[-1], 'cm')


def test_recover_after_a_failed_reconnect_resets_at_the_known_speed(emulator: SickEmulator,
                                                                    laser: SickLaser) -> None:
    """A failed connect leaves the line at 500000 baud; the reset must still reach the laser."""
    assert collect(laser, 1, within=2.0)
    emulator.fatal_error()
    timeouts = laser.stats.timeouts
    wait_silent(laser, 0.5, within=3.0)
    laser.reply_timeout = NO_REPLY_S    # a laser in a fatal error answers nothing but a reset
    with pytest.raises(DeviceTimeout):
        laser.connect()
    assert laser.baudrate == 500000 and emulator.fatal
    laser.reply_timeout = REPLY_S       # ... and that it answers
    laser.recover(reset_timeout=10 * REPLY_S)
    assert laser.state is LaserState.STREAMING and not emulator.fatal
    # One reset, heard at once: it went out at the known speed first, not at the line's 500000.
    assert emulator.commands.count(0x10) == 1 and laser.stats.timeouts == 1 + timeouts
    assert collect(laser, 1, within=3.0)


@pytest.mark.parametrize('miss', ['reset not heard', 'power cycled to 9600'])
def test_recover_when_the_first_reset_is_missed(emulator: SickEmulator, laser: SickLaser,
                                                miss: str) -> None:
    assert collect(laser, 1, within=2.0)
    if miss == 'reset not heard':
        emulator.miss_resets(1)         # heard at 38400 on the second round
    else:
        emulator.power_cycle()          # 38400 is wrong now: heard at 9600
        deadline = time.monotonic() + 20.0
        while emulator.device_baud != 9600:
            assert time.monotonic() < deadline, 'the emulator did not power up'
            time.sleep(0.01)
    emulator.fatal_error()
    wait_silent(laser, 0.5, within=3.0)
    laser.reply_timeout = REPLY_S       # the reset is answered (at one speed)
    laser.recover(reset_timeout=10 * REPLY_S)
    assert laser.state is LaserState.STREAMING and not emulator.fatal
    assert emulator.commands.count(0x10) == 1
    assert emulator.resets_missed == (1 if miss == 'reset not heard' else 0)
    assert emulator.device_baud == 38400 == laser.baudrate
    assert len(collect(laser, 2, within=3.0)) == 2


def test_recover_gives_up_within_the_reset_timeout(emulator: SickEmulator,
                                                   laser: SickLaser) -> None:
    """Resets nobody hears go round the speeds until the reset timeout, then connect reports it."""
    emulator.miss_resets(1000)
    emulator.fatal_error()
    laser.reply_timeout = NO_REPLY_S    # nothing is answered
    started = time.monotonic()
    with pytest.raises(DeviceTimeout):
        laser.recover(reset_timeout=2.0)
    took = time.monotonic() - started
    assert laser.state is LaserState.FAILED
    # heard only at 38400, once a round (4 x 0.05 s): several rounds within the timeout, then a
    # connect (8 x 0.05 s) — and not the default 30 s (the bound allows for a loaded machine)
    assert emulator.resets_missed >= 2 and 2.0 <= took < 2.0 + 5.0


def test_unplug_then_replug(emulator: SickEmulator, laser: SickLaser) -> None:
    assert collect(laser, 1, within=2.0)
    emulator.unplugged.set()
    wait_silent(laser, 0.5, within=3.0)
    emulator.unplugged.clear()
    scans = collect(laser, 2, within=3.0)
    assert len(scans) == 2 and laser.silent_for() < 0.5


def test_recover_from_a_powered_down_device_fails_cleanly(emulator: SickEmulator,
                                                          laser: SickLaser) -> None:
    emulator.unplugged.set()
    laser.reply_timeout = NO_REPLY_S    # nothing is answered
    started = time.monotonic()
    with pytest.raises(DeviceTimeout):
        laser.recover(reset_timeout=0.2)
    assert time.monotonic() - started < 5.0
    assert laser.state is LaserState.FAILED and laser.stats.timeouts >= 1
    emulator.unplugged.clear()
    laser.reply_timeout = REPLY_S       # now it answers
    laser.recover(reset_timeout=0.2)   # the device kept its state: a plain connect finds it
    assert collect(laser, 1, within=3.0)


def test_a_silent_line_times_out() -> None:
    with PtyDevice() as nobody:
        laser = SickLaser(nobody.path, reply_timeout=NO_REPLY_S)
        started = time.monotonic()
        with pytest.raises(DeviceTimeout):
            laser.connect()
        assert time.monotonic() - started < 5.0
        laser.close()


def test_wrong_type_is_refused() -> None:
    with SickEmulator(kind='PLS') as emulator:
        laser = SickLaser(emulator.path, kind='LMS', reply_timeout=REPLY_S)
        with pytest.raises(DeviceError, match='installation mode'):
            laser.connect()
        assert laser.state is LaserState.FAILED
        laser.close()


def test_reconnect_to_a_device_left_streaming_at_500k(emulator: SickEmulator) -> None:
    first = SickLaser(emulator.path, baudrate=500000, reply_timeout=REPLY_S)
    first.connect()
    first.close()                       # the device keeps streaming at 500000
    assert emulator.mode == 0x24 and emulator.device_baud == 500000
    second = SickLaser(emulator.path, baudrate=38400, resolution=1.0, reply_timeout=REPLY_S)
    try:
        second.connect()                # 9600, 19200, 38400 hear only noise; 500000 answers
        assert emulator.device_baud == 38400 and emulator.count == 181
        assert len(collect(second, 1, within=2.0)) == 1
    finally:
        second.close()


def test_emulator_answers_raw_requests() -> None:
    """The emulator's side of docs/protocols.md 1.4/1.5, spoken with plain pyserial."""
    with SickEmulator(scan_source=source) as emulator, \
            serial.Serial(emulator.path, 9600, timeout=0.05) as port:
        deframer = sick.Deframer()

        def ask(frame: bytes) -> sick.Telegram | None:
            port.write(frame)
            deadline = time.monotonic() + 10 * REPLY_S
            while time.monotonic() < deadline:
                got = deframer.feed(port.read(port.in_waiting or 1))
                if got:
                    return got[0]
            return None

        scan = ask(sick.one_scan_request())
        assert scan is not None and scan.command == 0xB0 and deframer.acks == 1
        assert sick.decode_b0(scan.data).count == 181
        assert ask(sick.variant_request(100, 25)).data[:1] == b'\x01'
        assert emulator.count == 401
        assert ask(sick.variant_request(180, 25)).data[:1] == b'\x00'
        config = sick.SickConfig(units_code=1)
        assert ask(sick.write_config_request(config)).data[:1] == b'\x00'   # not in install mode
        assert ask(sick.install_mode_request('PLS')).data == b'\x01'        # wrong password
        assert ask(sick.install_mode_request('LMS')).data == b'\x00'
        assert sick.decode_f7(ask(sick.write_config_request(config)).data) == (True, config)
        status = sick.decode_b1(ask(sick.status_request()).data)
        assert (status.operating_mode, status.scan_angle, status.resolution) == (0, 100, 25)
        assert ask(sick.request(0x66)).command == 0x92
        bad = bytearray(sick.type_request())
        bad[-1] ^= 0xFF
        port.write(bad)
        deadline = time.monotonic() + 10 * REPLY_S
        while deframer.naks == 0 and time.monotonic() < deadline:
            deframer.feed(port.read(port.in_waiting or 1))
        assert deframer.naks == 1
