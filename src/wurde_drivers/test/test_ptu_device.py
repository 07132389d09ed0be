"""The PTU-46 driver against the emulated unit over a real pty and pyserial."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator

import pytest
import serial

from wurde_drivers.errors import DeviceError, DeviceTimeout
from wurde_drivers.ports.serial_link import SerialLink
from wurde_drivers.ptu.codec import LimitHit, ResetDone
from wurde_drivers.ptu.device import BAUDRATE, Ptu46
from wurde_drivers.ptu.emulator import Ptu46Emulator

STEP = 185.1428 / 3600.0 * math.pi / 180.0     # rad per position
#: Longest wait for a reply the emulated unit gives: the driver's default, not a tighter guess
#: (a loaded machine can delay an answer by more than 0.1 s).
REPLY_S = 1.0


def wait_for(condition: Callable[[], bool], timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, 'condition not met before the deadline'
        time.sleep(0.01)


@pytest.fixture
def unit() -> Iterator[Ptu46Emulator]:
    with Ptu46Emulator() as emulator:
        yield emulator
    assert emulator.error is None


@pytest.fixture
def ptu(unit: Ptu46Emulator) -> Iterator[Ptu46]:
    driver = Ptu46(SerialLink(unit.path, BAUDRATE, retry_s=0.05), reply_timeout=REPLY_S)
    driver.connect(timeout=3.0)
    try:
        yield driver
    finally:
        driver.close()


def settle(ptu: Ptu46, timeout: float = 20.0) -> None:
    wait_for(lambda: not ptu.query().moving, timeout)


# -- the emulator, byte for byte -----------------------------------------------------------
def test_emulator_answers_the_manuals_examples(unit: Ptu46Emulator) -> None:
    # PTU-D46 manual 4.3-4.5 examples (echo on, verbose: the power-on state), docs/protocols.md 2.
    dialogue = [
        (b'PN ', b'PN * Minimum Pan position is -3090'),
        (b'PX ', b'PX * Maximum Pan position is 3090'),
        (b'TN ', b'TN * Minimum Tilt position is -907'),
        (b'TX ', b'TX * Maximum Tilt position is 604'),
        (b'PP3200 ', b'PP3200 ! Maximum allowable Pan position is 3090'),
        (b'PR ', b'PR * 185.1428 seconds arc per Pan position'),
        (b'PU ', b'PU * Maximum Pan speed is 2902 positions/sec'),
        (b'PS3300 ', b'PS3300 ! Pan speed cannot exceed 2902 positions/sec'),
        (b'PL20 ', b'PL20 ! Motor speed cannot be less than 31 pos/sec'),
        (b'PL40 ', b'PL40 *'),
        (b'PP ', b'PP * Current Pan position is 0'),
        (b'ED ', b'ED *'),
        (b'PP ', b'* Current Pan position is 0'),          # not echoed any more
        (b'FT ', b'*'),
        (b'pp\r', b'* 0'),                                # CR works as delimiter too
        (b'po4000 ', b'! Maximum allowable Pan position is 3090'),   # offsets are checked too
        (b'to-1000 ', b'! Minimum allowable Tilt position is -907'),
        (b'hp ', b'*'),
        (b'ht ', b'*'),
        (b'c ', b'* i'),
        (b'cv ', b'*'),
        (b'c ', b'* p'),                                  # what Player's GetMode compares
        (b'ci ', b'*'),
        (b'pa ', b'* 2000'),
        (b'v ', b'* Pan-Tilt Controller v2.14.0, (C)2006 Directed Perception, Inc., All Rights '
                b'Reserved'),
        (b'xyz ', b'! Illegal Command'),
        (b' r ', b'!T!T!P!P*'),
    ]
    with serial.Serial(unit.path, BAUDRATE, timeout=0) as port:
        for command, expected in dialogue:
            port.write(command)
            line = b''
            deadline = time.monotonic() + 2.0
            while not line.endswith(b'\r\n'):
                assert time.monotonic() < deadline, (command, line)
                port.timeout = max(0.0, deadline - time.monotonic())
                line += port.read(1)
            assert line == expected + b'\r\n'



def test_a_query_reads_where_the_axis_is_when_it_is_asked() -> None:
    """The emulator's thread stalled on a loaded machine (its last tick long ago): a query read
    the axis where that tick left it, and the next, after the catch-up, read a jump (the driver
    computed a speed 34 % too high in CI).  A real unit reads its position when asked.  The test
    is the emulator's thread here (not started): it ticks the unit to cruise, then lets 80 ms
    pass unticked before asking."""
    unit = Ptu46Emulator()
    try:
        unit.on_bytes(b'ps600 pp3000 ')
        t = time.monotonic() - 10.0
        for _ in range(200):                       # 1 s: 0.3 s up to 600 positions/s, then cruise
            unit.tick(t)
            t += unit.tick_s
        before, asked = unit.pan, time.monotonic()
        unit.tick(asked - 0.08)                    # the last tick: 80 ms ago (the step capped at 0.1 s)
        moved = unit.pan - before
        unit.on_bytes(b'pp ')
        late = unit.pan - before - moved           # what the query moved it on
        assert 0.08 * 600 - 2 * unit.tick_s * 600 <= late <= 0.1 * 600 + 1, (moved, late)
    finally:
        unit.stop()

# -- connect ------------------------------------------------------------------------------------
def test_connect_replays_players_init_and_reads_limits(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    assert bytes(unit.received).startswith(
        b' ft ed ci i pr tr pn px tn tx pl pu tl tu pp tp ')
    assert not unit.echo and not unit.verbose
    limits = ptu.limits
    assert limits.pan_resolution == pytest.approx(STEP)
    assert limits.pan_max == pytest.approx(3090 * STEP)
    assert limits.pan_min == pytest.approx(-3090 * STEP)
    assert limits.tilt_min == pytest.approx(-907 * STEP)
    assert limits.tilt_max == pytest.approx(604 * STEP)
    assert limits.pan_speed_max == pytest.approx(2902 * STEP)
    assert ptu.connected
    assert ptu.stats.telegrams >= 15


def test_limits_before_connect_and_a_missing_port_are_errors() -> None:
    driver = Ptu46(SerialLink('/nonexistent/ttyPTU', BAUDRATE))
    with pytest.raises(DeviceError):
        _ = driver.limits
    with pytest.raises(DeviceTimeout):
        driver.connect(timeout=0.5)


# -- commands -----------------------------------------------------------------------------------
def test_set_position_converts_with_the_queried_resolution(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.set_speed(2.5, 2.5)
    pan, tilt = ptu.set_position(0.1, -0.05)
    assert pan == pytest.approx(round(0.1 / STEP) * STEP)
    assert tilt == pytest.approx(round(-0.05 / STEP) * STEP)
    settle(ptu)                                    # arrived and stopped, as the unit says
    assert (unit.pan, unit.tilt) == (round(0.1 / STEP), round(-0.05 / STEP))
    state = ptu.query()
    assert state.pan == pytest.approx(pan) and state.tilt == pytest.approx(tilt)
    assert not state.moving


def test_set_position_is_clamped_to_the_limits(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    pan, tilt = ptu.set_position(10.0, -10.0)
    assert (pan, tilt) == (pytest.approx(ptu.limits.pan_max), pytest.approx(ptu.limits.tilt_min))
    assert b'pp3090 ' in unit.received and b'tp-907 ' in unit.received
    with pytest.raises(DeviceError):
        ptu.set_position(math.nan, 0.0)


def test_the_units_error_message_reaches_the_caller(ptu: Ptu46) -> None:
    with pytest.raises(DeviceError, match='Maximum allowable Pan position is 3090'):
        ptu.command('pp', 3200)
    with pytest.raises(DeviceError, match='Illegal Command'):
        ptu.command('zz')
    assert ptu.command('pp').number == 0          # the link still pairs replies right


def test_axes_move_over_time_at_their_speed(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    assert ptu.set_speed(600 * STEP, 600 * STEP) == pytest.approx((600 * STEP, 600 * STEP))
    ptu.set_position(600 * STEP, 0.0)
    start = time.monotonic()
    wait_for(lambda: 100 < unit.pan < 500, 2.0)
    state = ptu.query()
    assert state.moving and state.pan_speed == pytest.approx(600 * STEP)
    wait_for(lambda: ptu.query().pan_velocity > 300 * STEP, 1.0)
    assert ptu.query().pan_velocity <= 600 * STEP * 1.3
    settle(ptu)
    # 600 positions at 600 pos/s with 2000 pos/s^2: 0.3 s up, 0.7 s cruise, 0.3 s down
    assert time.monotonic() - start > 1.2
    assert unit.pan == 600


def test_speeds_are_clamped_to_the_units_bounds(ptu: Ptu46) -> None:
    pan, tilt = ptu.set_speed(100.0, 0.0)
    assert pan == pytest.approx(ptu.limits.pan_speed_max)
    assert tilt == pytest.approx(ptu.limits.tilt_speed_min)
    assert ptu.query().pan_speed == pytest.approx(pan)


def test_acceleration_is_set(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    pan, tilt = ptu.set_acceleration(4000 * STEP, 1000 * STEP)
    assert (pan, tilt) == (pytest.approx(4000 * STEP), pytest.approx(1000 * STEP))
    assert ptu.command('pa').number == 4000 and ptu.command('ta').number == 1000


def test_velocity_mode_and_halt(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.set_velocity_mode(True)
    assert ptu.set_speed(-300 * STEP, 0.0) == (pytest.approx(-300 * STEP), 0.0)
    wait_for(lambda: unit.pan < -100, 2.0)
    ptu.halt()
    stopped = unit.pan
    state = ptu.query()
    assert state.pan == pytest.approx(stopped * STEP, abs=2 * STEP)
    assert state.pan_speed == 0.0
    ptu.set_velocity_mode(False)
    assert ptu.command('c').text == 'i'


def test_slaved_mode_waits_for_await(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.set_speed(2000 * STEP, 2000 * STEP)
    ptu.command('s')
    ptu.command('pp', 400)
    assert unit.pan == 0 and not unit.moving
    ptu.command('a', timeout=3.0)                  # answers when the move has ended
    assert unit.pan == 400
    ptu.command('i')


def test_verbose_feedback_still_parses(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.command('fv')
    assert unit.verbose
    assert ptu.command('pr').text == '185.1428 seconds arc per Pan position'
    assert ptu.query().pan == 0.0
    assert 'Directed Perception' in ptu.command('v').text


def test_reset_recentres(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.set_speed(2500 * STEP, 2500 * STEP)
    ptu.set_position(300 * STEP, 0.0)
    wait_for(lambda: unit.pan == 300)
    unit.reset_s = 0.2
    start = time.monotonic()
    ptu.reset()
    assert time.monotonic() - start >= 0.15
    assert unit.pan == 0 and ptu.query().pan == 0.0


# -- asynchronous events ----------------------------------------------------------------------
def test_poll_returns_limit_hits(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    start = time.monotonic()
    assert ptu.poll(0.1) == []
    assert 0.09 <= time.monotonic() - start < 0.1 + 1.5   # (slack for a loaded machine)
    unit.inject_limit_hit('tilt')
    assert ptu.poll(2.0) == [LimitHit('tilt')]


def test_limit_hit_during_a_command_is_kept_for_poll(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    unit.inject_limit_hit('pan')
    wait_for(lambda: unit.bytes_out > 0)
    ptu.query()
    assert ptu.poll(0.0) == [LimitHit('pan')]
    unit.inject_garbage(b'!T!T!P!P*\r\n')
    assert ptu.poll(2.0) == [ResetDone()]


# -- faults ---------------------------------------------------------------------------------------
def test_garbage_between_replies_is_skipped(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    unit.inject_garbage()
    unit.inject_garbage(b'\x00\xff#%&\r\n')
    skipped = ptu.stats.bytes_skipped
    assert ptu.query().pan == 0.0
    assert ptu.bad_lines >= 1 and ptu.stats.bytes_skipped > skipped


def test_a_garbled_reply_times_out_then_the_driver_recovers(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    unit.corrupt_next(1)
    with pytest.raises(DeviceTimeout):
        ptu.command('pp')
    assert not ptu.connected and ptu.stats.timeouts == 1
    assert ptu.query().pan == 0.0
    assert ptu.connected


def test_a_silent_unit_times_out_within_the_deadline(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    unit.silent.set()
    start = time.monotonic()
    with pytest.raises(DeviceTimeout):
        ptu.halt()
    assert time.monotonic() - start < REPLY_S + 1.5     # (slack for a loaded machine)
    unit.silent.clear()
    ptu.halt()


def test_a_power_cycled_unit_is_initialised_again(unit: Ptu46Emulator, ptu: Ptu46) -> None:
    ptu.set_speed(2500 * STEP, 2500 * STEP)
    ptu.set_position(200 * STEP, 0.0)
    unit.unplug()
    with pytest.raises(DeviceTimeout):
        ptu.query()
    with pytest.raises(DeviceTimeout):             # the reconnect attempt times out as well
        ptu.query()
    unit.replug(power_cycle=True)
    wait_for(lambda: unit.echo)                    # back with the power-on defaults
    state = ptu.query()                            # reconnects: ft ed ci i and limits again
    assert state.pan == 0.0
    assert not unit.echo and not unit.verbose
    assert bytes(unit.received).count(b' ft ed ci i ') >= 2


def test_a_vanished_port_is_reopened(unit: Ptu46Emulator) -> None:
    link = SerialLink(unit.path, BAUDRATE, retry_s=0.05)
    ptu = Ptu46(link, reply_timeout=REPLY_S)
    ptu.connect()
    link.close()                                   # as SerialLink does when the port fails
    link.stats.disconnects += 1
    assert ptu.query().pan == 0.0
    assert ptu.connected and link.is_open
    ptu.close()
    ptu.close()
