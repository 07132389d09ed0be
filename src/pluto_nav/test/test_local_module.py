"""localModule against the simulated Pluto, all real processes: its five streams, the setter rules
of Post_Pose, odometry that stops, and inputs that are missing."""

from __future__ import annotations

import math
import os
import pathlib
import re
import signal
import time

import numpy as np
import pytest
from nav_fixture import (EXACT, Watcher, angle_error, interpolate_truth, module, pluto_config, processes,
                         seconds)

from pluto_nav.geometry import compose, relative
from pluto_nav.loc_proxy import LocProxy
from pluto_nav.resume import ResumeState, read_resume, write_resume
from pluto_nav.streams import STREAMS

MOUNT_X = 0.2     # config/pluto: the laser 0.2 m ahead of the robot centre

DR, LASER_DR, POST, POSE, LASER_POSE = STREAMS


def drive(watcher: Watcher, trans: float, rot: float) -> None:
    drive = watcher.objects['PlutoBaseDrive']
    drive.requests.trans_velocity.set_value(trans)
    drive.requests.rot_velocity.set_value(rot)
    drive.publish_request()


def _watcher(*extra: str) -> Watcher:
    streams = {'PlutoBaseTruth': 'Egomotion', 'PlutoBaseMotion': 'Egomotion', 'PlutoBaseDrive': 'RobotDrive',
               'PlutoLaser/Timing': 'FVectorState', 'Localization/Status': 'FVectorState'}
    streams.update({name: 'LocalizationPose' for name in (DR, LASER_DR, POSE, LASER_POSE)})
    streams.update({name: 'FVectorState' for name in extra})
    return Watcher(streams)


def test_dead_reckoning_follows_the_robot_and_the_laser_stream_is_at_the_scans_time(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, elements=EXACT)
    watcher = _watcher()
    try:
        with processes(directory, ['PlutoBase', 'PlutoLaser', 'PlutoDMU', 'PlutoWrist'], ('local_module', [])):
            watcher.until(lambda: len(watcher.events[DR]) >= 3, 'dead reckoning')
            start = len(watcher.events[LASER_DR])

            def far_enough() -> bool:
                last = watcher.events[DR][-1].pose
                return len(watcher.events[LASER_DR]) >= start + 10 and math.hypot(last.x - 3.0, last.y - 7.5) > 0.8

            # An arc: 0.3 m/s, 0.3 rad/s, commanded until ten scans went by and it is 0.8 m away.
            watcher.until(far_enough, 'ten scans and 0.8 m of driving', every=lambda: drive(watcher, 0.3, 0.3))
            drive(watcher, 0.0, 0.0)
    finally:
        watcher.close()
    truth = watcher.events['PlutoBaseTruth']
    dead_reckoning = watcher.events[DR]
    moved = 0.0
    checked = 0
    for message in dead_reckoning:
        true = interpolate_truth(truth, seconds(message))
        if true is None:
            continue
        pose = message.pose
        assert math.hypot(pose.x - true[0], pose.y - true[1]) < 0.02, (pose, true)
        assert angle_error(pose.theta, true[2]) < 0.02
        moved = max(moved, math.hypot(pose.x - 3.0, pose.y - 7.5))
        checked += 1
    assert checked > 20 and moved > 0.5       # it drove, and dead reckoning followed the truth
    # Pose (3) is (0) while nobody improves it, setter 0.
    for a, b in zip(dead_reckoning, watcher.events[POSE]):
        assert (a.pose.x, a.pose.y, a.pose.theta) == pytest.approx((b.pose.x, b.pose.y, b.pose.theta))
        assert b.cmd_flags == 0
    # Stream (1) is stamped at the scans' centre times, at the laser's pose then.
    scan_times = {round(seconds(m), 6) for m in watcher.events['PlutoLaser/Timing']}
    laser = watcher.events[LASER_DR]
    seen_from = min(scan_times)         # the test's subscription may have matched after the first scans
    assert {round(seconds(m), 6) for m in laser if seconds(m) >= seen_from} <= scan_times
    for message in laser[1:]:
        true = interpolate_truth(truth, seconds(message))
        if true is None:
            continue
        expected = (true[0] + MOUNT_X * math.cos(true[2]), true[1] + MOUNT_X * math.sin(true[2]))
        assert math.hypot(message.pose.x - expected[0], message.pose.y - expected[1]) < 0.02
        assert message.pose.z == pytest.approx(0.5)         # the laser's mounting height
        covariance = np.array(message.covariance).reshape(3, 3)
        assert np.all(np.linalg.eigvalsh(covariance) > 0)   # the increment's, never zero


def test_post_pose_moves_pose_but_not_dead_reckoning_and_the_setter_rules_hold(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, elements=EXACT)
    watcher = _watcher()
    other = Watcher({}, name='SlamLike')
    user = LocProxy(watcher.manager, 1 + 4 + 8)
    slam = LocProxy(other.manager, 4)

    def status() -> list[int]:
        events = watcher.events['Localization/Status']
        return list(events[-1].element) if events else []

    def pump_both() -> None:
        other.pump()
        slam.update()                 # sends its pose once the localModule's reader is matched

    try:
        with processes(directory, ['PlutoBase', 'PlutoLaser'], ('local_module', [])):
            # A laser scan placed: the laser's mounting (its RangeFinder info) is known.
            watcher.until(lambda: user.setter == 0 and watcher.events[LASER_DR] and watcher.events[DR],
                          'setter 0, a scan placed, dead reckoning')
            before = watcher.events[DR][-1].pose
            # A user sets the robot pose (setter -1): Pose jumps there, dead reckoning does not.
            user.set_pose((5.0, 7.0, 0.5), -1)      # held until matched; user.setter sends it
            watcher.until(lambda: user.setter == -1, 'setter -1')
            count = len(watcher.events[POSE])
            watcher.until(lambda: len(watcher.events[POSE]) > count + 2, 'poses after the set')
            pose = watcher.events[POSE][-1]
            assert (pose.pose.x, pose.pose.y, pose.pose.theta) == pytest.approx((5.0, 7.0, 0.5), abs=1e-6)
            assert pose.cmd_flags == -1
            after = watcher.events[DR][-1].pose
            assert (after.x, after.y) == pytest.approx((before.x, before.y), abs=1e-6)
            # NaN is refused and counted.
            assert user.set_pose((math.nan, 1.0, 0.0), -1)       # matched by now: sent at once
            watcher.until(lambda: len(status()) == 4 and status()[3] == 1, 'one refusal counted')
            # An estimator takes the setter (a laser pose, setter 2) ...
            slam.set_pose((4.0, 7.0, 0.0), 2)
            watcher.until(lambda: user.setter == 2, 'setter 2', every=pump_both)
            # ... and then a user's robot pose, another setter's pose and its release are refused.
            user.set_pose((1.0, 1.0, 0.0), -1)
            user.set_pose((1.0, 1.0, 0.0), 1)
            user.set_pose((0.0, 0.0, 0.0), 0)
            watcher.until(lambda: status()[3] == 4, 'three more refusals', every=pump_both)
            assert user.setter == 2
            watcher.until(lambda: watcher.events[POSE][-1].cmd_flags == 2, 'a Pose with setter 2')
            laser = watcher.events[POSE][-1]
            assert laser.cmd_flags == 2
            # The laser pose (4, 7, 0) means the robot centre is 0.2 m behind it.
            assert (laser.pose.x, laser.pose.y) == pytest.approx((4.0 - MOUNT_X, 7.0), abs=1e-3)
            # The holder releases it.
            slam.set_pose((0.0, 0.0, 0.0), 0)
            watcher.until(lambda: user.setter == 0, 'setter released', every=pump_both)
    finally:
        other.close()
        watcher.close()


def _placed(events: dict, stamp: float) -> bool:
    """Whether the scan at ``stamp`` is out on both laser streams, (1) and (4)."""
    return all(any(abs(seconds(m) - stamp) < 1e-6 for m in events[s]) for s in (LASER_DR, LASER_POSE))


def test_scans_timed_before_the_lasers_info_are_placed_with_its_mounting_once_it_comes(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """On a loaded machine a laser's first scans came before its RangeFinder info, and the
    localModule placed them at the robot's centre: slamModule's map, started from such a
    Laser_Pose, lay 0.2 m off.  Here the test is the laser: scans timed first, the info later."""
    from wurde_drivers.streams.laser import LaserStreams
    directory = pluto_config(tmp_path, elements=EXACT)
    watcher = _watcher()
    laser = LaserStreams('PlutoLaser')
    laser.register(watcher.manager)
    events = watcher.events
    try:
        with processes(directory, ['PlutoBase'], ('local_module', [])):
            watcher.until(lambda: len(events[DR]) >= 3, 'dead reckoning')
            early = seconds(events[DR][-1])                 # covered by the odometry
            laser.publish_scan([1.0] * 361, centre_stamp=early, arrival_stamp=early)
            # The module reads its inputs every loop, and publishes dead reckoning in each.
            count = len(events[DR])
            watcher.until(lambda: len(events[DR]) >= count + 5, 'five more dead-reckoning steps')
            laser.publish_info(count=361, max_range=8.0, mount_x=MOUNT_X)
            watcher.until(lambda: _placed(events, early), 'the early scan placed')
            late = seconds(events[DR][-1])
            laser.publish_scan([1.0] * 361, centre_stamp=late, arrival_stamp=late)
            watcher.until(lambda: _placed(events, late), 'the later scan placed')
        robot = {round(seconds(m), 6): m.pose for m in events[DR]}
        assert len(events[LASER_DR]) == len(events[LASER_POSE]) == 2
        for placed in events[LASER_DR] + events[LASER_POSE]:
            centre = robot[round(seconds(placed), 6)]          # standing still, facing east
            assert (placed.pose.x, placed.pose.y) == pytest.approx((centre.x + MOUNT_X, centre.y), abs=1e-6)
    finally:
        watcher.close()


def test_when_the_odometry_stops_the_status_says_so_and_the_covariance_grows(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, elements=EXACT)
    watcher = _watcher()

    def status() -> list:
        events = watcher.events['Localization/Status']
        return [events[-1].element, events[-1].data] if events else [[], []]

    try:
        with processes(directory, ['PlutoBase'], ('local_module', [])) as running:
            watcher.until(lambda: len(status()[0]) == 4 and status()[0][0] == 1 and watcher.events[DR],
                          'odometry fresh and dead reckoning from it')
            assert status()[0][1] == 0          # no DMU running: dead reckoning from odometry alone
            base = running['PlutoBase'].process
            os.kill(base.pid, signal.SIGSTOP)
            try:
                watcher.until(lambda: status()[0][0] == 0, 'odometry stale')
                first = status()[1][1]
                watcher.until(lambda: status()[1][1] > first + 0.05, 'the covariance grows')
            finally:
                os.kill(base.pid, signal.SIGCONT)
            watcher.until(lambda: status()[0][0] == 1, 'odometry back')
    finally:
        watcher.close()


def test_a_bad_pose_file_is_refused_with_file_line_and_reason(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path)
    pose_file = tmp_path / 'start.txt'
    pose_file.write_text('# start\n1.0 2.0 nope\n')
    with module('pluto_nav', 'local_module', directory, '-p', str(pose_file)) as process:
        assert process.process.wait(timeout=60) == 2
    assert f'{pose_file}:2: not a number' in process.stderr
    (tmp_path / 'no-start.xml').write_text('<?xml version="1.0"?><map name="x" version="1.0">'
                                           '<wall x1="0" y1="0" x2="1" y2="0"/></map>')
    with module('pluto_nav', 'local_module', directory, '-m', str(tmp_path / 'no-start.xml')) as process:
        assert process.process.wait(timeout=60) == 2
    assert 'no place "start"' in process.stderr


START = (3.0, 7.5, 0.0)     # config/pluto's map: the place "start"
FIRST_STEP = re.compile(r'first Pose since the restart: x=(?P<x>\S+) y=(?P<y>\S+) theta=(?P<theta>\S+) '
                        r'at odometry stamp (?P<stamp>\S+);')


def _local_module(directory: pathlib.Path, restart: int, **env: str):
    """A localModule process as the MCP starts it the ``restart``-th time (0: the first), its
    state file ``localModule.resume`` in ``directory``."""
    return module('pluto_nav', 'local_module', directory, env={
        'WURDE_MCP_RESTART': str(restart), 'WURDE_MCP_STATE': str(directory / 'localModule.resume'), **env})


def _xyt(message) -> tuple[float, float, float]:
    return message.pose.x, message.pose.y, message.pose.theta


@pytest.mark.parametrize('noise', ['exact', 'realistic'])
def test_a_restarted_local_module_goes_on_where_the_killed_one_was(
        ros_domain: int, tmp_path: pathlib.Path, noise: str) -> None:
    """The MCP restarts a killed localModule (WURDE_MCP_RESTART=1): its first Pose is where the
    robot is, not the map's start, although the robot drove on while no localModule ran.

    Its first Pose must be the dead process's last Pose advanced by the odometry between the two
    stamps (what the old process would have published had it lived) within 2 cm, and have turned
    as the robot turned within 2 degrees: the turn comes from the DMU, which ran on (its reading at
    the save is in the resume file).  With exact odometry (EXACT) dead reckoning equals the truth,
    so the resumed Pose must be the truth too, within 2 cm and 2 degrees; with config/pluto's noisy
    odometry dead reckoning has drifted from the truth before the kill, so only those two checks
    apply.  The first Pose is the one the new process logs: a subscriber may hear a new process's
    Poses only from a later one on (discovery), reckoned over more steps."""
    directory = pluto_config(tmp_path, elements=EXACT if noise == 'exact' else None)
    resume_file = directory / 'localModule.resume'
    watcher = _watcher()
    events = watcher.events

    def steer() -> None:
        """0.4 m/s east along the corridor, weaving onto the line y = 7.9 (the heading changes)."""
        truth = events['PlutoBaseTruth']
        y, theta = (truth[-1].location.y, truth[-1].location.theta) if truth else (START[1], 0.0)
        heading = max(-0.3, min(0.3, 0.8 * (7.9 - y)))
        drive(watcher, 0.4, max(-0.5, min(0.5, 2.0 * (heading - theta))))

    def away() -> bool:
        return bool(events[POSE]) and math.dist(_xyt(events[POSE][-1])[:2], START[:2]) > 1.2 and resume_file.exists()

    try:
        with processes(directory, ['PlutoBase', 'PlutoDMU']):
            with _local_module(directory, 0) as old:
                watcher.until(lambda: bool(events[POSE]), 'the first Pose')
                watcher.until(away, '1.2 m from the start, a resume file written', every=steer)
                old.process.send_signal(signal.SIGKILL)
                old.process.wait(timeout=30)
                # Stamps are the simulation's, which never runs ahead of the wall clock: every
                # Pose of the dead process is stamped before this.
                cutoff = time.time() + 0.05
            with _local_module(directory, 1) as new:
                watcher.until(lambda: any(seconds(m) > cutoff for m in events[POSE]),
                              "the new process's first Pose", every=steer)
                drive(watcher, 0.0, 0.0)
                watcher.until(lambda: FIRST_STEP.search(new.stderr), 'the new process saying its first step')
    finally:
        watcher.close()
    assert 'resuming at' in new.stderr
    old_last = [m for m in events[POSE] if seconds(m) <= cutoff][-1]
    # The new process's first Pose as it logged it: the watcher may not hear a new publisher's
    # first Poses (discovery on a loaded machine), and a later one is reckoned over more steps.
    first_step = FIRST_STEP.search(new.stderr)
    new_first = tuple(float(v) for v in first_step.group('x', 'y', 'theta'))
    heard_first = next(m for m in events[POSE] if seconds(m) > cutoff)
    t0, t1 = seconds(old_last), float(first_step['stamp'])
    assert t1 > cutoff
    true0, true1 = interpolate_truth(events['PlutoBaseTruth'], t0), interpolate_truth(events['PlutoBaseTruth'], t1)
    assert true0 is not None and true1 is not None
    gap = math.dist(true0[:2], true1[:2])
    assert gap > 0.2, gap            # the robot drove on while no localModule ran
    assert math.dist(START[:2], new_first[:2]) > 1.2
    # Against the old process's last Pose advanced by the odometry between the two stamps (the
    # Poses are stamped with the odometry sample they were reckoned from).
    odometry = {seconds(m): (m.location.x, m.location.y, m.location.theta) for m in events['PlutoBaseMotion']}

    def reading(stamp: float) -> tuple[float, float, float]:
        nearest = min(odometry, key=lambda s: abs(s - stamp))
        assert abs(nearest - stamp) < 1e-5, (nearest, stamp)
        return odometry[nearest]

    expected = compose(_xyt(old_last), relative(reading(t0), reading(t1)))
    error = math.dist(new_first[:2], expected[:2])
    heading_error = angle_error(new_first[2], expected[2])
    true_error = math.dist(new_first[:2], true1[:2])
    print(f'{noise}: resumed Pose {100 * error:.2f} cm, {heading_error:.4f} rad from the old Pose + odometry; '
          f'{100 * true_error:.2f} cm, {angle_error(new_first[2], true1[2]):.4f} rad from the truth; '
          f'{gap:.2f} m driven in {t1 - t0:.2f} s without a localModule')
    # The heading turned in the gap comes from the DMU, which ran on (its reading at the saved
    # one is in the resume file), not from the odometry, whose steady drift (config/pluto: rad
    # per metre driven) the DMU does not share: the turn is the truth's.
    # Within the 2 degrees: the DMU's filtered heading lags a changing turn rate by up to
    # its time constant times the rate (32 ms x 0.5 rad/s, 0.016 rad), which its delayed stamps
    # make up for only at a steady rate.  The odometry's turn was 0.03-0.06 rad off.
    turned = angle_error(new_first[2] - old_last.pose.theta, true1[2] - true0[2])
    assert 'resumed without the DMU' not in new.stderr
    assert error < 0.02 and turned < math.radians(2.0), (error, turned, heading_error)
    if noise == 'exact':        # where the robot is; its heading as the DMU turned (within 2 degrees,
        assert true_error < 0.02    # its lag: 32 ms x a turn rate changed by up to 1 rad/s)
        assert angle_error(new_first[2], true1[2]) < math.radians(2.0)
    assert seconds(heard_first) >= t1 and heard_first.cmd_flags == 0
    covariance = np.array(heard_first.covariance).reshape(3, 3)
    assert np.trace(covariance) >= np.trace(np.array(old_last.covariance).reshape(3, 3))


def test_a_first_start_ignores_the_resume_file_and_bad_or_unwritable_ones_are_said(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """A new run (WURDE_MCP_RESTART 0) starts at the map's start whatever a resume file says; a
    restart whose resume file is garbage says so and starts there too; a resume file that cannot
    be written is said once and the module runs on."""
    directory = pluto_config(tmp_path, elements=EXACT)
    resume_file = directory / 'localModule.resume'
    watcher = _watcher()
    events = watcher.events
    try:
        with processes(directory, ['PlutoBase']):
            resume_file.write_text('{"format": "pluto_nav.resume", "version": 1, "odometry": {"st')
            with _local_module(directory, 2) as garbage:
                watcher.until(lambda: bool(events[POSE]), 'the first Pose after a garbage resume file')
                assert _xyt(events[POSE][0]) == pytest.approx(START, abs=1e-6)
                watcher.until(lambda: f'resume file {resume_file} is unusable (not JSON (truncated?)'
                              in garbage.stderr, 'the garbage resume file said')
            count = len(events[POSE])
            write_resume(resume_file, ResumeState(
                odometry_stamp=1.0, odometry=(0.0, 0.0, 0.0), dead_reckoning=(9.0, 7.5, 1.0),
                dead_reckoning_covariance=np.eye(3) * 0.01, pose=(9.0, 7.5, 1.0), pose_covariance=None))
            with _local_module(directory, 0) as fresh:
                watcher.until(lambda: len(events[POSE]) > count and resume_file.exists(),
                              'the first Pose of a new run, its resume file')
                assert _xyt(events[POSE][count]) == pytest.approx(START, abs=1e-6)
                # The process's log is read by a thread of the test: wait for the line, do not race it.
                watcher.until(lambda: 'a first start' in fresh.stderr, 'the new run saying it is a first start')
                # The file is the new run's now (standing at the start).
                watcher.until(lambda: read_resume(resume_file)[0] is not None, 'a readable resume file')
                state, _ = read_resume(resume_file)
                assert state.pose == pytest.approx(START, abs=1e-6)
            # A state file in a directory that is not there cannot be written; that is said once,
            # and the module runs on.
            nowhere = tmp_path / 'no-such-directory'
            with _local_module(directory, 0, WURDE_MCP_STATE=str(nowhere / 'localModule.resume')) as unwritable:
                watcher.until(lambda: 'cannot write the resume file' in unwritable.stderr, 'the write failure said')
                said = time.time()
                watcher.until(lambda: seconds(events[POSE][-1]) > said + 1.5, 'Poses 1.5 s later')
                assert unwritable.process.poll() is None
                # (each log line is on stderr twice: the WURDE logger's and rclpy's)
                assert unwritable.stderr.count('[ERROR] localModule: localModule: cannot write the resume file') == 1, \
                    unwritable.stderr
                assert f'{nowhere}/localModule.resume' in unwritable.stderr
    finally:
        watcher.close()


def test_scans_are_placed_after_a_backlog_and_held_until_the_laser_s_mount_comes(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """A loaded machine: the localModule stopped while 12 s of odometry and 24 scans queue up, and
    the laser's RangeFinder info (its mount) only after it has worked through them (as carmen_log
    play into the MCP's modules had it in a fresh-clone make test: 85 of 95 scans placed).  Every
    scan is placed at its time on the dead reckoning and published once the mount is known."""
    from wurde_core import CommsManager, Pose, Time
    from wurde_core.interfaces import Egomotion, FVectorState, RangeFinder
    directory = pluto_config(tmp_path)
    watcher = _watcher()
    supplier = CommsManager('FakeRobot')
    supplier.set_no_sleep()
    motion, timing, laser = Egomotion('PlutoBaseMotion'), FVectorState('PlutoLaser/Timing'), RangeFinder('PlutoLaser')
    for obj in (motion, timing, laser):
        obj.set_auto_timestamp(False)
        obj.set_queue_mode(True)                     # as the drivers and carmen_log play send them
        supplier.register_supplier(obj)
    try:
        with module('pluto_nav', 'local_module', directory) as local:
            for obj in (motion, timing):             # the watcher reads them too: two readers
                watcher.until(lambda o=obj: o.peers() >= 2, f'the localModule reading {obj}', every=supplier.step)
            local.process.send_signal(signal.SIGSTOP)
            start = time.time()
            try:
                for k in range(121):                 # 10 Hz odometry, a scan every 0.5 s, 0.1 m/s ahead
                    stamp = start + 0.1 * k
                    motion.data.location = Pose(0.01 * k, 0.0, 0.0)
                    motion.data.tv, motion.data.rv = 0.1, 0.0
                    motion.data.timestamp = Time(stamp)
                    assert motion.publish_data()
                    if k % 5 == 2 and k < 120:
                        timing.data.element = [361]
                        timing.data.timestamp = Time(stamp)
                        assert timing.publish_data()
            finally:
                local.process.send_signal(signal.SIGCONT)
            watcher.until(lambda: any(abs(seconds(m) - (start + 12.0)) < 1e-3 for m in watcher.events[DR]),
                          'the backlog of odometry worked through', every=supplier.step)
            assert not watcher.events[LASER_DR]              # no mount yet: nothing placed at the centre
            laser.info.x_offset.set_value(MOUNT_X)
            laser.info.z_offset.set_value(0.5)
            laser.publish_info()
            watcher.until(lambda: len(watcher.events[LASER_DR]) >= 24, 'every scan placed', every=supplier.step)
    finally:
        supplier.clean_up()
        watcher.close()
    placed = watcher.events[LASER_DR]
    assert len(placed) == 24
    for message in placed:
        t = seconds(message) - start
        assert message.pose.x == pytest.approx(3.0 + 0.1 * t + MOUNT_X, abs=1e-4)    # from the start, at its time
