"""The avoidModule's laser protection, refusals, threads and release through real processes: laser
slow/stop (6) in front of a wall, backward motion not the laser's, a dead laser process (7, stop),
NaN refused and counted, start_activity starting the drive too, release (-10) writing one stop and
nothing more; and the SICK's fatal error (-1 ranges, 7) from a laser the test supplies."""

from __future__ import annotations

import math
import pathlib

from avoid_fixture import RADIUS, Avoider, chain, write_world
from drive_fixture import program
from wurde_core import Time
from wurde_core.interfaces import RangeFinder
from wurde_testing.parameters import ParameterTool


def _zero(test: Avoider) -> bool:
    return test.avoid.velocities == (0.0, 0.0)


def test_laser_slow_stop_dead_laser_nan_and_release(ros_domain: int, tmp_path: pathlib.Path) -> None:
    walls = write_world(tmp_path, (6.0, 4.0), [], (3.0, 2.0, 0.0))
    test = Avoider()
    test.walls = walls
    a = test.avoid
    try:
        with chain(tmp_path) as processes:
            test.children = dict(processes)
            test.ready()
            # The distances are tunables (ros2 param): a slow-down inside the stop is refused.
            tool = ParameterTool('/avoidModule')
            try:
                assert tool.get('laser.stop', 'laser.slow', 'goto.reach') == [0.15, 1.0, 3.0]
                taken, reason = tool.set('laser.slow', 0.1)
                assert not taken and 'stop < slow' in reason
                assert tool.set('laser.slow', 1.2) == (True, '')
            finally:
                tool.close()
            # Forward with laser protection only (cmdFlags 20): slowed (6), then stopped short of
            # the east wall (x = 6) without touching it.
            test.until(lambda: a.code == 6 and test.tv == 0.0 and _zero(test), 'stopped by the laser',
                       every=lambda: a.velocity(0.4, 0.0, laser=True), timeout=60)
            assert any(m.element[0] == 6 and 0.0 < m.data[0] < 0.4 for m in test.avoid_statuses)   # slowed first
            assert 6.0 - RADIUS - 0.4 < test.pose[0] < 6.0 - RADIUS and test.lowest > RADIUS
            # Backwards is not the laser's to judge: code 0 again, moving.
            x_stop = test.pose[0]
            test.until(lambda: test.pose[0] < x_stop - 0.2 and a.code == 0, 'backing off',
                       every=lambda: a.velocity(-0.2, 0.0, laser=True))
            # The laser process dies: no scan for longer than its period allows -> 7 and a stop.
            laser = test.children.pop('laser')
            laser.process.terminate()
            test.until(lambda: a.code == 7 and test.tv == 0.0 and _zero(test), 'stopped by the dead laser',
                       every=lambda: a.velocity(-0.2, 0.0, laser=True), timeout=30)
            assert 'laser no scan for' in processes['avoid'].stderr
            # Without laser protection the same command drives (the laser is not needed for it).
            test.until(lambda: test.tv < 0.0 and a.code == 0, 'driving without laser protection',
                       every=lambda: a.velocity(-0.2, 0.0))
            # NaN: refused whole and counted in element[2].
            before = a.refused
            a.velocity(math.nan, 0.0)
            test.until(lambda: a.refused == before + 1, 'the NaN counted')
            a.goto(math.inf, 1.0)
            test.until(lambda: a.refused == before + 2, 'the infinite goal counted')
            assert 'refused command' in processes['avoid'].stderr
            # start_activity on the avoidModule also starts the drive's thread.
            test.drive.release_robot()
            test.until(lambda: test.drive.code == -10, 'drive thread stopped')
            a.start_activity()
            test.until(lambda: test.drive.code in (0, -1), 'drive thread started by the avoid start')
            # Release: -10, one stop to the drive, then nothing (a command is ignored).
            test.until(lambda: test.drive.code == 0, 'the drive running')
            echoes, moved = len(test.accepted), len(test.truths)
            a.release_robot()
            test.until(lambda: a.goto_status == -10, 'avoid thread stopped')
            a.velocity(0.3, 0.0)
            test.until(lambda: 'ignored' in processes['avoid'].stderr, 'the command ignored')
            a.start_activity()
            test.until(lambda: a.goto_status == 0, 'avoid thread started again')
            # The robot may still be slowing down from the drive's last command (the base limits
            # its deceleration; on a loaded machine the truth comes late): wait for the stop, then
            # check that nothing drove it forwards (the ignored 0.3) and that the drive got at
            # most the one stop.
            test.until(lambda: test.tv == 0.0, 'the robot stopped after the release', timeout=10)
            assert all(m.tv <= 0.0 for m in test.truths[moved:]), [m.tv for m in test.truths[moved:]]
            after = [list(m.velocity) for m in test.accepted[echoes:]]
            assert len(after) <= 1 and all(v == [0.0, 0.0] for v in after), after
    finally:
        test.close()


def _fan(laser: RangeFinder) -> None:
    info = laser.info
    info.max_range.set_value(8.0)
    info.uniform.set_value(True)
    info.x_offset.set_value(0.2)
    info.theta_offset.set_value(-math.pi / 2)
    info.theta_separation.set_value(math.pi / 360)
    laser.publish_info()


def test_fatal_laser_error_stops_with_seven(ros_domain: int, tmp_path: pathlib.Path) -> None:
    write_world(tmp_path, (6.0, 4.0), [], (3.0, 2.0, 0.0))
    test = Avoider()
    laser = RangeFinder('TestLaser')
    laser.set_auto_timestamp(False)
    test.manager.register_supplier(laser)
    scans = {'n': 0, 'value': 5.0}

    def scan() -> None:
        scans['n'] += 1
        laser.data.ranges = [scans['value']] * 361
        laser.data.timestamp = Time(scans['n'] * 0.2)
        laser.publish_data()

    try:
        with program('pluto_motion', 'avoid_module', tmp_path, '-L', 'TestLaser') as avoid:
            test.children = {'avoid': avoid}
            _fan(laser)

            def drive_and_scan() -> None:
                scan()
                test.avoid.velocity(0.3, 0.0, laser=True)

            # Normal on a status after the avoidModule took a laser-protected command (before its
            # first scan the laser is 7 too: no scan yet).
            def fine() -> bool:
                test.avoid._take_echoes()
                echo = getattr(test.avoid, 'echo', None)
                return echo is not None and echo[0] == 20 and test.avoid.stamp > echo[2] and test.avoid.code == 0

            try:
                test.until(fine, 'laser fine', every=drive_and_scan, period=0.2, timeout=30)
            except AssertionError as error:
                raise AssertionError(f'{error}; avoid code {test.avoid.code}; its log: {avoid.stderr[-800:]}') from None
            scans['value'] = -1.0                       # the SICK's fatal error: every range -1
            try:
                test.until(lambda: test.avoid.code == 7 and 'fatal error (negative ranges)' in avoid.stderr,
                           'fatal error seen', every=drive_and_scan, period=0.2)
            except AssertionError as error:
                raise AssertionError(f'{error}; avoid code {test.avoid.code}; its log: {avoid.stderr[-800:]}') from None
            assert test.avoid.velocities == (0.0, 0.0)
            scans['value'] = 5.0
            test.until(lambda: test.avoid.code == 0, 'laser back', every=drive_and_scan, period=0.2)
    finally:
        test.close()
