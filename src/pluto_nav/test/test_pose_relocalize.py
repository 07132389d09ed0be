"""A localModule killed while the robot drives, restarted after the robot drove on without it:
the Pose is within 0.1 m and 2 degrees of the truth within a few scans of the poseModule (issue
38).  The new process reckons the gap from the saved readings: the turn from the DMU that ran on,
the path from the odometry (here drifting steadily, 0.05 rad per metre), and its first laser
increment carries the gap's covariance, so the poseModule's gates open as far as the gap is
unknown.  Before, the gap's turn came from the odometry and the increment was taken as sure: a
heading a few degrees off stayed up to 12 s in the soak."""

from __future__ import annotations

import math
import pathlib
import signal

from nav_fixture import Watcher, angle_error, interpolate_truth, pluto_config, processes, seconds
from test_local_module import _local_module, drive

from pluto_nav.streams import STREAMS

POSE = STREAMS[3]
ALL = ['PlutoBase', 'PlutoLaser', 'PlutoDMU', 'PlutoWrist']
#: The odometry's steady heading drift (rad per metre driven).
DRIFT = '0.05'
#: m the robot drives along the corridor with no localModule.
GAP = 1.5
#: Scans the poseModule may use, after the restart, to bring the Pose within 0.1 m and 2 degrees.
SCANS = 10


def _error(watcher: Watcher, message) -> tuple[float, float] | None:
    true = interpolate_truth(watcher.events['PlutoBaseTruth'], seconds(message))
    if true is None:
        return None
    return math.hypot(message.pose.x - true[0], message.pose.y - true[1]), angle_error(message.pose.theta, true[2])


def _x(watcher: Watcher) -> float:
    return watcher.events['PlutoBaseTruth'][-1].location.x


def test_a_local_module_restarted_after_a_drive_is_relocalized_within_a_few_scans(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, elements={'odometry-noise': {'drift': DRIFT}})   # office, noise on
    resume_file = directory / 'localModule.resume'
    watcher = Watcher({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseDrive': 'RobotDrive', POSE: 'LocalizationPose',
                       'pose/status': 'FVectorState'})
    events = watcher.events
    try:
        with processes(directory, ALL, ('pose_module', [])):
            with _local_module(directory, 0) as old:
                watcher.until(lambda: bool(events[POSE]) and events[POSE][-1].cmd_flags == 1 and resume_file.exists()
                              and bool(events['PlutoBaseTruth']) and bool(events['pose/status'])
                              and events['pose/status'][-1].element[2] >= 5,
                              'the poseModule holding the setter, 5 scans used', timeout=120)
                start = _x(watcher)
                watcher.until(lambda: _x(watcher) > start + 0.5, 'half a metre east', timeout=60,
                              every=lambda: drive(watcher, 0.5, 0.0))
                settled = _error(watcher, events[POSE][-1])
                old.process.send_signal(signal.SIGKILL)
                old.process.wait(timeout=30)
            killed_at = _x(watcher)
            watcher.until(lambda: _x(watcher) > killed_at + GAP, f'{GAP} m east with no localModule', timeout=60,
                          every=lambda: drive(watcher, 0.5, 0.0))
            watcher.until(lambda: abs(events['PlutoBaseTruth'][-1].tv) < 1e-6, 'stopped',
                          every=lambda: drive(watcher, 0.0, 0.0))
            used = events['pose/status'][-1].element[2]
            with _local_module(directory, 1) as new:
                watcher.until(lambda: 'resuming at' in new.stderr, 'the new process saying it resumed')

                def back() -> bool:
                    latest = events[POSE][-1]
                    error = _error(watcher, latest) if latest.cmd_flags == 1 else None
                    scans = events['pose/status'][-1].element[2] - used
                    within = error is not None and error[0] < 0.1 and error[1] < math.radians(2.0)
                    assert within or scans <= SCANS, f'{scans} scans after the restart the Pose is {error} off'
                    return within and scans > 0

                watcher.until(back, 'the Pose within 0.1 m and 2 degrees of the truth', timeout=60)
    finally:
        watcher.close()
    # Localized before the kill, by the same measure (the robot driving at 0.5 m/s).
    assert settled is not None and settled[0] < 0.1 and settled[1] < math.radians(2.0), settled
