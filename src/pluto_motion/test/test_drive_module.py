"""driveModule with the dummy base in a 6 m x 4 m room, all real processes, driven through DriveProxy:
velocity commands move the base with the acceleration limited, a NaN is refused and counted, silence
times out (-1) and stops the base, the thread is released (-10) and started again, the regulator
turns to a heading and holds it, sonar protection stops short of the wall (3 front, 4 back) and the
bumpers stop the base (1 front, 2 back)."""

from __future__ import annotations

import math
import pathlib
from collections.abc import Callable
from typing import Any

import pytest
from drive_fixture import Driver, angle_error, program, robot, room_config, seconds
from wurde_testing.parameters import ParameterTool
from wurde_testing import ChildProcess, find_executable

#: The driveModule's defaults: linear acceleration limit (m/s^2) and timeout (s, Pluto 6.1).
TV_ACCEL = 0.5
TIMEOUT = 4.0


def _fastest_ramp(statuses: list, window: float = 0.3) -> float:
    """The largest change of data[0] (the commanded linear velocity) over ``window`` s of the
    drive's own clock, divided by ``window`` + one loop's worth of slack (0.1 s)."""
    worst = 0.0
    for i, early in enumerate(statuses):
        for late in statuses[i + 1:]:
            span = seconds(late) - seconds(early)
            if span > window:
                break
            worst = max(worst, abs(late.data[0] - early.data[0]) / (span + 0.1))
    return worst


def _first_with_code(driver: Driver, code: int) -> Any:
    """The first status with element[0] == ``code`` (the loop that saw the bumper)."""
    return next(m for m in driver.statuses if m.element[0] == code)


def _base_zero(driver: Driver) -> Callable[[], bool]:
    """Whether the base's command state is zero."""
    return lambda: bool(driver.base_states) and list(driver.base_states[-1].velocity) == [0.0, 0.0]


def test_velocity_acceleration_nan_timeout_and_release(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)
    driver = Driver()
    d = driver.drive
    try:
        with robot(directory) as processes:
            driver.children = processes
            driver.until(lambda: d.code == 0 and driver.pose is not None, 'status and truth', timeout=60)
            x0 = driver.pose[0]
            first_status = len(driver.statuses)

            def forward() -> None:
                d.velocity(0.3, 0.0)

            driver.until(lambda: driver.pose[0] > x0 + 0.4, 'driven 0.4 m east', every=forward)
            assert d.velocities == pytest.approx((0.3, 0.0), abs=1e-6)
            assert abs(driver.pose[1] - 2.0) < 0.01                 # straight: angular velocity 0
            # The acceleration limit, on the drive's own clock: its command ramps at 0.5 m/s^2
            # (the base alone would allow 1.0).  Not on the truth: a base process stalled by a
            # loaded machine catches up in simulated time with the newest command, which
            # compresses any ramp it was sent.
            ramp = [m for m in driver.statuses[first_status:] if len(m.data) == 2]
            assert max(m.data[0] for m in ramp) == pytest.approx(0.3)
            assert _fastest_ramp(ramp) <= TV_ACCEL * 1.1
            assert sum(1 for m in ramp if 0.0 < m.data[0] < 0.3) >= 5     # reached in steps, not at once

            # NaN: refused whole and counted; the last good command goes on.
            before = d.refused
            d.velocity(math.nan, 0.0)
            driver.until(lambda: d.refused == before + 1, 'the NaN counted')
            d.heading(0.3, math.inf)
            driver.until(lambda: d.refused == before + 2, 'the infinite heading counted')
            assert d.velocities == pytest.approx((0.3, 0.0), abs=1e-6)
            assert 'refused command' in processes['drive'].stderr

            # Silence: after about 4 s (Pluto 6.1) element[0] = -1 and the base stops.  Timed on
            # the drive's own clock, from its echo of the last command it accepted to its first
            # status saying -1 (the test's own clock would add a loaded machine's delays).
            echoes = len(driver.accepted)
            forward()
            driver.until(lambda: len(driver.accepted) > echoes, 'the last command accepted')
            last = seconds(driver.accepted[-1])
            driver.until(lambda: d.code == -1, 'the timeout', timeout=TIMEOUT + 60)
            timed_out = next(seconds(m) for m in driver.statuses if seconds(m) > last and m.element[0] == -1)
            assert TIMEOUT - 0.05 <= timed_out - last <= TIMEOUT + 1.0
            driver.until(lambda: driver.tv == 0.0 and d.velocities == (0.0, 0.0), 'the base stopped', timeout=30)
            assert list(driver.base_states[-1].velocity) == [0.0, 0.0]
            assert driver.pose[0] < 6.0 - 0.35                      # never reached the wall

            # release_robot: thread stopped, commands ignored; start_activity: back to normal.
            d.release_robot()
            driver.until(lambda: d.code == -10, 'thread stopped')
            x1 = driver.pose[0]
            d.velocity(0.3, 0.0)
            driver.until(lambda: 'ignored' in processes['drive'].stderr, 'the command ignored')
            assert driver.tv == 0.0 and driver.pose[0] == pytest.approx(x1, abs=1e-6)
            d.start_activity()
            driver.until(lambda: d.code == 0, 'thread started')
            driver.until(lambda: driver.pose[0] < x1 - 0.1, 'driving again', every=lambda: d.velocity(-0.3, 0.0))
    finally:
        driver.close()


def test_regulator_sonar_and_bumpers(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)
    driver = Driver()
    d = driver.drive
    north = math.pi / 2
    try:
        with robot(directory) as processes:
            driver.children = processes
            driver.until(lambda: d.code == 0 and driver.pose is not None, 'status and truth', timeout=60)
            # Regulator with sonar protection: turn to north, hold it, stop short of the north
            # wall (y = 4) because of the front sonar, without touching it.
            driver.until(lambda: d.code == 3 and driver.tv == 0.0, 'stopped by the front sonar',
                         every=lambda: d.heading(0.4, north, sonar=True))
            assert angle_error(driver.pose[2], north) < 0.03
            assert 3.0 < driver.pose[1] < 4.0 - 0.35 - 0.05
            assert abs(driver.pose[0] - 3.0) < 0.2                  # turned smoothly, then straight
            assert 'base odometry' in processes['drive'].stderr    # no localModule: the fall-back
            # Without sonar protection the regulator drives on into the wall: front bumper.
            driver.until(lambda: d.code == 1, 'front bumper', every=lambda: d.heading(0.3, north))
            assert list(_first_with_code(driver, 1).data) == [0.0, 0.0]      # zero at once, in that loop
            driver.until(lambda: driver.tv == 0.0, 'stopped at the wall', timeout=30)
            driver.until(_base_zero(driver), 'the base commanded zero', timeout=30)
            assert d.velocities == (0.0, 0.0)
            assert driver.pose[1] == pytest.approx(4.0 - 0.35, abs=0.02)
            # Still pressed: a forward command is not executed, a backward one is (code 0 again).
            d.heading(0.3, north)
            driver.until(lambda: d.code == 0, 'the new command clears the latch')
            assert d.velocities[0] == 0.0
            # Backwards with sonar protection: the back sonar stops it short of the south wall.
            driver.until(lambda: d.code == 4 and driver.tv == 0.0, 'stopped by the back sonar',
                         every=lambda: d.velocity(-0.6, 0.0, sonar=True), timeout=40)
            assert 0.35 + 0.05 < driver.pose[1] < 1.5
            # And without: the back bumper.
            driver.until(lambda: d.code == 2, 'back bumper', every=lambda: d.velocity(-0.3, 0.0))
            assert list(_first_with_code(driver, 2).data) == [0.0, 0.0]
            driver.until(lambda: driver.tv == 0.0, 'stopped at the wall', timeout=30)
            assert driver.pose[1] == pytest.approx(0.35, abs=0.02)
            driver.until(_base_zero(driver), 'the base commanded zero', timeout=30)
            assert d.velocities == (0.0, 0.0)
    finally:
        driver.close()


def test_the_limits_are_tunables_set_while_running_and_from_a_params_file(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """``ros2 param set /driveModule max_tv 0.2`` caps the drive at once; out of range is refused;
    ``ros2 param dump`` of the drive, given back with ``--params-file``, starts it capped."""
    directory = room_config(tmp_path)
    driver = Driver()
    d = driver.drive
    try:
        with robot(directory) as processes:
            driver.children = processes
            driver.until(lambda: d.code == 0 and driver.pose is not None, 'status and truth', timeout=60)
            tool = ParameterTool('/driveModule')
            try:
                assert tool.get('max_tv', 'tv_accel', 'timeout') == [1.0, TV_ACCEL, TIMEOUT]
                taken, reason = tool.set('max_tv', 9.0)
                assert not taken and 'out of range' in reason
                assert tool.set('max_tv', 0.2) == (True, '')
                dump = tool.dump()
            finally:
                tool.close()
            first, first_base = len(driver.statuses), len(driver.base_states)

            def at_the_limit() -> bool:
                # Both the drive's status and the base's command state (a separate topic, which
                # a loaded machine may deliver later than the status) show the new limit.
                return (any(len(m.data) == 2 and m.data[0] > 0.19 for m in driver.statuses[first:])
                        and any(s.velocity[0] > 0.19 for s in driver.base_states[first_base:]))

            driver.until(at_the_limit, 'driving at the new limit', every=lambda: d.velocity(0.5, 0.0))
            statuses = driver.statuses[first:]
            assert max(m.data[0] for m in statuses if len(m.data) == 2) <= 0.2 + 1e-6   # float32 on the wire
            assert max(s.velocity[0] for s in driver.base_states) <= 0.2 + 1e-6   # float32 on the wire
            d.velocity(0.0, 0.0)
        params = tmp_path / 'drive.yaml'
        params.write_text(dump)
        with robot(directory, '--ros-args', '--params-file', str(params)) as processes:
            tool = ParameterTool('/driveModule')
            try:
                assert tool.get('max_tv', 'max_rv') == [0.2, 1.5]
            finally:
                tool.close()
            assert processes['drive'].process.poll() is None
    finally:
        driver.close()


CARMEN_INI = """\
# the drive's limits in the robot's parameter file (wurde_core.carmen_tunables)
[*]
driveModule_max_tv   0.25
driveModule_max_rv   99        # beyond the tunable's range: refused, the drive keeps its own
"""
FOLLOW_DAEMON = """\
<?xml version="1.0"?>
<wurde-config>
  <module name="driveModule"><option name="param_daemon" value="on"/></module>
</wurde-config>
"""


def test_the_limits_follow_carmen_s_parameter_daemon(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """With its role configuration's ``param_daemon`` option the drive takes carmen.ini's
    ``driveModule_*`` values from a daemon that starts after it, refuses one out of range with the
    reason, and follows ``param_tool set`` while it runs: the base is held to each new limit."""
    directory = room_config(tmp_path)
    (directory / 'carmen.ini').write_text(CARMEN_INI)
    (directory / 'role-config.xml').write_text(FOLLOW_DAEMON)
    driver = Driver()
    d = driver.drive
    tool: ParameterTool | None = None

    def capped(limit: float) -> None:
        """Asked for 0.5 m/s, the drive commands ``limit``: coming down from a higher limit it
        brakes to it (at its deceleration: never faster again), then holds it."""
        first = len(driver.statuses)
        driver.until(lambda: any(len(m.data) == 2 and limit - 0.01 < m.data[0] <= limit + 1e-6
                                 for m in driver.statuses[first:]),
                     f'driving at {limit} m/s', every=lambda: d.velocity(0.5, 0.0))
        speeds = [m.data[0] for m in driver.statuses[first:] if len(m.data) == 2]
        held = next(i for i, v in enumerate(speeds) if v <= limit + 1e-6)
        assert all(a >= b - 1e-6 for a, b in zip(speeds[:held], speeds[1:held + 1])), speeds
        assert max(speeds[held:]) <= limit + 1e-6, speeds

    try:
        with robot(directory, '-g', str(directory / 'role-config.xml')) as processes:
            driver.children = processes
            driver.until(lambda: d.code == 0 and driver.pose is not None, 'status and truth', timeout=60)
            tool = ParameterTool('/driveModule')
            assert tool.get('max_tv', 'max_rv') == [1.0, 1.5]           # no daemon yet
            with ChildProcess([find_executable('wurde_mcp', 'param_daemon')], cwd=directory) as daemon:
                daemon.expect('param_daemon ready', timeout=60)
                driver.until(lambda: tool.get('max_tv') == [0.25], 'the daemon\'s max_tv taken')
                driver.until(lambda: 'driveModule_max_rv = 99.0 refused' in processes['drive'].stderr,
                             'the out-of-range max_rv reported')
                assert tool.get('max_rv') == [1.5]
                capped(0.25)
                with ChildProcess([find_executable('wurde_mcp', 'param_tool'), 'set',
                                   'driveModule_max_tv', '0.15']) as setter:
                    assert setter.process.wait(timeout=60) == 0, setter.stderr
                driver.until(lambda: tool.get('max_tv') == [0.15], 'the change followed')
                capped(0.15)
                d.velocity(0.0, 0.0)
    finally:
        if tool is not None:
            tool.close()
        driver.close()


def test_the_status_says_ready_once_the_drive_hears_the_base(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """element[2]: 0 while the drive runs without a base, 1 once the base's sonar is in and the base
    reads the drive's commands, 0 again a second after the base is gone (its sonar stale)."""
    directory = room_config(tmp_path)
    driver = Driver()
    d = driver.drive
    try:
        with program('pluto_motion', 'drive_module', directory) as drive:
            driver.children = {'drive': drive}
            driver.until(lambda: d.code == 0 and len(d.element) == 3, 'the drive heard', timeout=60)
            assert not d.ready and d.element[2] == 0
            with program('wurde_drivers', 'dummy_base', directory, '-n', 'PlutoBase') as base:
                driver.children['base'] = base
                driver.until(lambda: d.ready, 'ready with the base', timeout=60)
                driver.until(lambda: driver.pose is not None, 'the truth')
                x0 = driver.pose[0]
                driver.until(lambda: driver.pose[0] > x0 + 0.1, 'driven with sonar protection',
                             every=lambda: d.velocity(0.3, 0.0, sonar=True))
                del driver.children['base']
            driver.until(lambda: not d.ready, 'not ready without the base', timeout=30)
            assert d.element[2] == 0
    finally:
        driver.close()
