"""The driveModule's control without processes: commands parsed or refused, the timeout, the
bumper latch, the sonar groups (the sides, which the room test cannot reach) and the regulator."""

from __future__ import annotations

import math

import pytest

from pluto_motion.drive_command import CommandRefused, Mode, parse_command
from pluto_motion.drive_control import DriveController, DriveSettings
from pluto_motion.sonar_guard import FRONT, SIDES, SonarGuard
from test_sonar_guard import HALF, echo
from test_sonar_guard import RING as LAYOUT

RING = [2 * math.pi * i / 16 for i in range(16)]
FAR = [8.0] * 16


@pytest.mark.parametrize(('flags', 'velocity', 'position', 'why'), [
    (2, [0.1, 0.0], [], 'cmdFlags 2'),
    (0, [0.1], [], 'velocity needs 2'),
    (0, [math.nan, 0.0], [], 'not finite'),
    (11, [0.2], [0.0, math.inf], 'not finite'),
    (1, [0.2], [1.0], 'position needs 2'),
])
def test_bad_commands_are_refused_with_the_reason(flags: int, velocity: list[float], position: list[float],
                                                  why: str) -> None:
    with pytest.raises(CommandRefused, match=why):
        parse_command(flags, velocity, position)


def test_good_commands_and_release() -> None:
    assert parse_command(-1, [], []) is None
    c = parse_command(11, [0.3], [5.0, 1.0])
    assert c is not None and (c.mode, c.tv, c.heading, c.sonar, c.cmd_flags) == (Mode.REGULATOR, 0.3, 1.0, True, 11)


def test_timeout_stops_and_reports_minus_one() -> None:
    control = DriveController(DriveSettings(timeout=4.0))
    control.accept(parse_command(0, [0.2, 0.0], []), now=0.0)
    t = 0.0
    while t < 3.9:
        t += 0.05
        control.step(t, 0.05, heading=None, sonar=None)
    assert control.output[0] == pytest.approx(0.2) and control.code == 0
    while t < 4.6:
        t += 0.05
        control.step(t, 0.05, heading=None, sonar=None)
    assert control.code == -1 and control.output == (0.0, 0.0)


def test_side_sonar_slows_and_code_five() -> None:
    guard = SonarGuard()
    guard.set_bearings(RING)
    ranges = list(FAR)
    ranges[4] = 0.1                       # straight left, inside the side slow-down band
    tv, code = guard.limit(0.5, ranges)
    assert code == SIDES and 0.0 < tv < 0.5
    ranges[4] = 0.04                      # closer than the side stop distance
    assert guard.limit(0.5, ranges) == (0.0, SIDES)
    assert guard.limit(0.0, ranges) == (0.0, 0)       # turning in place is never limited


def test_a_slow_command_goes_on_to_near_the_stop_distance() -> None:
    """The sonar slows the robot to the speed the free way allows (the drive's maximum at ``slow``,
    0 at ``stop``), not to a share of the speed asked for: at 0.1 m/s the robot stopped for good
    with 0.45 m free, under the creep speed, short of an avoid goto's goal near a wall."""
    control = DriveController(DriveSettings())
    control.guard.set_layout(LAYOUT, HALF)
    control.accept(parse_command(10, [0.1, 0.0], []), now=0.0)          # velocity, sonar on
    t = 0.0
    for free in (1.5, 0.6, 0.45, 0.3, 0.2, 0.08):
        ranges = [echo(s, [('x', 0.35 + free, -0.3, 0.3)]) for s in LAYOUT]
        for _ in range(10):
            t += 0.05
            tv, _ = control.step(t, 0.05, heading=None, sonar=ranges)
        if free >= 0.3:
            assert tv == pytest.approx(0.1), free
        elif free >= 0.2:
            assert 0.05 <= tv < 0.1 and control.code == FRONT           # slowed, still going
        else:
            assert tv == 0.0 and control.code == FRONT


def test_bumper_latch_forbids_motion_towards_it_until_a_new_command() -> None:
    control = DriveController()
    control.accept(parse_command(0, [0.3, 0.0], []), now=0.0)
    control.step(0.1, 0.1, heading=None, sonar=None)
    assert control.set_bumpers(True, False)
    assert control.step(0.2, 0.1, heading=None, sonar=None) == (0.0, 0.0) and control.code == 1
    control.accept(parse_command(0, [0.3, 0.0], []), now=0.3)
    assert control.step(0.4, 0.1, heading=None, sonar=None)[0] == 0.0 and control.code == 0
    control.accept(parse_command(0, [-0.3, 0.0], []), now=0.5)
    assert control.step(0.6, 0.1, heading=None, sonar=None)[0] < 0.0


def test_regulator_turns_in_place_then_drives_along_the_heading() -> None:
    control = DriveController()
    control.accept(parse_command(1, [0.4], [0.0, math.pi]), now=0.0)
    tv, rv = control.step(0.05, 0.05, heading=0.0, sonar=None)
    assert tv == 0.0 and rv > 0.0         # 180 degrees off: turn first
    for i in range(60):                   # 3 s: within the 4 s timeout
        control.step(0.1 + 0.05 * i, 0.05, heading=math.pi, sonar=None)
    assert control.output == pytest.approx((0.4, 0.0))
    assert control.step(3.2, 0.05, heading=None, sonar=None)[0] < 0.4    # no heading: slowing to a stop
