"""Odometry calibration end to end (Pluto 6.1, 7.1): a dummy base whose odometry counts 3 % too much
distance and 3 % too little rotation, pose_i's ``calibrate`` against the wall in front (through the
real poseModule's find-wall and the driveModule), the file written, the driveModule restarted reads
it and sets it in the base, and the odometry over a measured run is then within 1 % of the
simulator's truth.  All real processes."""

from __future__ import annotations

import contextlib
import math
import pathlib
import re

import pytest
from drive_fixture import Driver, program, room_config
from lxml import etree
from wurde_core.interfaces import Egomotion

from pluto_nav.odometry_calibration import read_calibration

DEVICES = {'PlutoBase': 'dummy_base', 'PlutoLaser': 'dummy_sick', 'PlutoDMU': 'dummy_dmu',
           'PlutoWrist': 'dummy_wrist'}
#: The base's calibration error: odometry distance x1.03, rotation x0.97.
SCALE, TURN_SCALE = 1.03, 0.97


def _config(directory: pathlib.Path) -> pathlib.Path:
    room_config(directory)
    path = directory / 'sim-config.xml'
    tree = etree.parse(str(path))
    noise = tree.getroot().find('odometry-noise')
    noise.set('scale', str(SCALE))
    noise.set('turn-scale', str(TURN_SCALE))
    tree.write(str(path))
    return directory


class Run(Driver):
    """The Driver with the base's odometry recorded too."""

    def __init__(self) -> None:
        super().__init__()
        self.motion = Egomotion('PlutoBaseMotion')
        self.motion.set_queue_mode(True)
        self.manager.register_consumer(self.motion)
        self.odometry: list = []

    def pump(self) -> None:
        super().pump()
        while self.motion.get_next_data():
            self.odometry.append(self.motion.data.ros_message())

    def settle(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Stop; once truth and odometry stand, both poses."""
        def still() -> bool:
            return (bool(self.truths) and bool(self.odometry) and self.truths[-1].tv == 0.0
                    and self.truths[-1].rv == 0.0 and self.odometry[-1].tv == 0.0 and self.odometry[-1].rv == 0.0)
        self.until(still, 'the robot stands', every=lambda: self.drive.velocity(0.0, 0.0), period=0.2)
        o = self.odometry[-1].location
        return self.pose, (o.x, o.y, o.theta)

    def leg(self, tv: float, rv: float, done) -> tuple[float, float]:
        """Drive until ``done(start truth, truth)``; the truth's and the odometry's change (distance
        or angle, by what moved)."""
        truth0, odo0 = self.settle()
        self.until(lambda: done(truth0, self.pose), 'the leg', timeout=60,
                   every=lambda: self.drive.velocity(tv, rv), period=0.2)
        truth1, odo1 = self.settle()
        if rv == 0.0:
            return math.dist(truth0[:2], truth1[:2]), math.dist(odo0[:2], odo1[:2])
        turn = lambda a, b: abs(math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))  # noqa: E731
        return turn(truth0, truth1), turn(odo0, odo1)

    def measured_run(self) -> tuple[float, float]:
        """Forward 1 m and back, left 1 rad and back: the odometry's worst relative error in
        distance and in rotation."""
        moved = lambda a, b: math.dist(a[:2], b[:2]) >= 1.0  # noqa: E731
        turned = lambda a, b: abs(math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))) >= 1.0  # noqa: E731
        legs = [self.leg(0.3, 0.0, moved), self.leg(-0.3, 0.0, moved)]
        turns = [self.leg(0.0, 0.4, turned), self.leg(0.0, -0.4, turned)]
        return (max(abs(o / t - 1) for t, o in legs), max(abs(o / t - 1) for t, o in turns))


def test_pose_i_calibrates_the_odometry_the_drive_sets_it(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = _config(tmp_path)
    path = directory / 'odometry-calibration.yaml'
    run = Run()
    try:
        with contextlib.ExitStack() as stack:
            for name, executable in DEVICES.items():
                run.children[name] = stack.enter_context(program('wurde_drivers', executable, directory, '-n', name))
            for name in ('local_module', 'pose_module'):
                run.children[name] = stack.enter_context(program('pluto_nav', name, directory))
            drive = program('pluto_motion', 'drive_module', directory)
            run.children['drive'] = drive
            run.drive.start_activity()
            run.until(lambda: run.drive.code == 0 and bool(run.odometry) and bool(run.truths), 'the drive runs',
                      timeout=90)
            before = run.measured_run()
            with program('pluto_nav', 'pose_i', directory, '-t', '60') as pose_i:
                pose_i.expect('pose_i ready', timeout=60)
                pose_i.send('calibrate 1.5 0.5')
                answer = pose_i.expect('calibrat', timeout=240)
                pose_i.send('quit')
                assert pose_i.process.wait(timeout=30) == 0
            assert answer.startswith('ok calibration'), answer
            found = read_calibration(path)
            # The scales undo the error: true / raw odometry.
            assert found.distance == pytest.approx(1 / SCALE, rel=0.01), answer
            assert found.rotation == pytest.approx(1 / TURN_SCALE, rel=0.01), answer
            assert re.search(r'was 1\.00000 1\.00000', answer), answer
            # The driveModule restarted reads the file and sets it in the base.
            del run.children['drive']
            drive.stop()
            drive = stack.enter_context(program('pluto_motion', 'drive_module', directory))
            run.children['drive'] = drive
            run.drive.start_activity()
            run.until(lambda: bool(run.base_states) and list(run.base_states[-1].force[:2]) == pytest.approx(
                [found.distance, found.rotation], rel=1e-5), 'the base took the calibration', timeout=90)
            run.until(lambda: run.drive.code == 0, 'the drive runs again', timeout=60,
                      every=run.drive.start_activity, period=1.0)
            after = run.measured_run()
            print(f'\nodometry error before: distance {before[0]:.2%} rotation {before[1]:.2%}; '
                  f'after: distance {after[0]:.2%} rotation {after[1]:.2%}; file {found}')
            assert before[0] > 0.025 and before[1] > 0.025, before
            assert after[0] < 0.01 and after[1] < 0.01, (before, after)
    finally:
        run.close()


def test_a_wrong_calibration_file_stops_the_drive_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = room_config(tmp_path)
    (directory / 'odometry-calibration.yaml').write_text('distance-scale: 1.01\nrotation-scale: 7\n')
    with program('pluto_motion', 'drive_module', directory) as drive:
        assert drive.process.wait(timeout=60) == 2
        lines = drive.stderr.strip().splitlines()
    assert lines and lines[-1].endswith('odometry-calibration.yaml:2: rotation-scale 7.0 is not in [0.5, 2.0]'), \
        drive.stderr
    assert 'Traceback' not in drive.stderr
