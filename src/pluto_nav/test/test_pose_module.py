"""poseModule with the simulated Pluto (noise on), all real processes, driven through pose_i as a
user would: it localizes, holds setter 1, finds the wall in front, gives the setter back when
stopped and takes a pose set by hand (Pluto 7.1's procedure), recovering from where it was set.
Its matcher's settings are tunables (``ros2 param set /poseModule match.max_range ...``)."""

from __future__ import annotations

import math
import pathlib
import re

import pytest
from nav_fixture import Watcher, angle_error, interpolate_truth, module, pluto_config, processes, seconds
from wurde_testing.parameters import ParameterTool

from pluto_nav.streams import STREAMS

POSE = STREAMS[3]
ALL = ['PlutoBase', 'PlutoLaser', 'PlutoDMU', 'PlutoWrist']


def _reply(pose_i, command: str) -> str:
    """Send a pose_i command; its one-line answer (``ok ...`` or ``error ...``)."""
    pose_i.send(command)
    line = pose_i.expect(' ', timeout=90)
    while not (line.startswith('ok') or line.startswith('error')):
        line = pose_i.expect(' ', timeout=90)
    return line


def _error_now(watcher: Watcher) -> tuple[float, float]:
    truth = watcher.events['PlutoBaseTruth']
    for message in reversed(watcher.events[POSE]):
        true = interpolate_truth(truth, seconds(message))
        if true is not None:
            return (math.hypot(message.pose.x - true[0], message.pose.y - true[1]),
                    angle_error(message.pose.theta, true[2]))
    return math.inf, math.inf


def _matched(status) -> int:
    """Scans used whose lines matched a wall (pose/status element[2] - element[3])."""
    return int(status.element[2] - status.element[3])


def _unmatched_run(statuses) -> int:
    """Most scans used in a row, among ``statuses``, with no line matched."""
    best = 0
    for k, later in enumerate(statuses):
        earlier = next(m for m in statuses[:k + 1] if _matched(m) == _matched(later))
        best = max(best, int(later.element[2] - earlier.element[2]))
    return best


def test_pose_module_localizes_finds_the_wall_and_takes_a_pose_set_by_hand(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path)          # config/pluto: office, odometry/laser/DMU noise on
    watcher = Watcher({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseDrive': 'RobotDrive', POSE: 'LocalizationPose',
                       'pose/status': 'FVectorState'})

    def drive(trans: float) -> None:
        obj = watcher.objects['PlutoBaseDrive']
        obj.requests.trans_velocity.set_value(trans)
        obj.requests.rot_velocity.set_value(0.0)
        obj.publish_request()

    try:
        with processes(directory, ALL, ('local_module', []), ('pose_module', [])), \
                module('pluto_nav', 'pose_i', directory) as pose_i:
            pose_i.expect('pose_i ready', timeout=60)
            # (the truth and the status too: the checks below read their newest, and each
            # stream's subscription matches in its own time)
            watcher.until(lambda: watcher.events[POSE] and watcher.events[POSE][-1].cmd_flags == 1
                          and watcher.events['PlutoBaseTruth'] and watcher.events['pose/status'],
                          'the pose module holds the setter', timeout=90)
            # Find the wall in front: from (3, 7.5) facing east, the corridor's end wall at x = 20,
            # 20 - 3 - 0.2 (the laser's mounting) = 16.8 m ahead.
            wall = _reply(pose_i, 'wall')
            found = re.match(r'ok wall (\d+) gamma (\S+) rho (\S+)', wall)
            assert found, wall
            assert int(found.group(1)) > 5
            assert float(found.group(2)) == pytest.approx(0.0, abs=0.03)
            assert float(found.group(3)) == pytest.approx(16.8, abs=0.1)
            # Drive 3 m east along the corridor; the Pose stays on the truth.
            start = watcher.events['PlutoBaseTruth'][-1].location.x
            watcher.until(lambda: watcher.events['PlutoBaseTruth'][-1].location.x > start + 3.0, 'three metres east',
                          timeout=90, every=lambda: drive(0.4))
            drive(0.0)
            watcher.until(lambda: abs(watcher.events['PlutoBaseTruth'][-1].tv) < 1e-6, 'stopped',
                          every=lambda: drive(0.0))
            position, heading = _error_now(watcher)
            assert position < 0.05 and heading < math.radians(1.0), (position, heading)
            # The matcher's tunables: a gate below the other is refused with the settings' reason;
            # a 0.5 m range (no wall expected) leaves every scan unmatched until it is put back.
            status = watcher.events['pose/status']
            tool = ParameterTool('/poseModule')
            try:
                assert tool.get('match.gate_probability', 'match.max_range') == [0.99, pytest.approx(81.82)]
                taken, reason = tool.set('match.fallback_gate_probability', 0.9)
                assert not taken and 'fallback_gate_probability must not be below' in reason
                assert tool.set('match.max_range', 0.5) == (True, '')
                first = len(status)
                watcher.until(lambda: _unmatched_run(status[first:]) >= 3, 'three scans used, none matched')
                assert tool.set('match.max_range', 81.82) == (True, '')
            finally:
                tool.close()
            again = len(status)
            watcher.until(lambda: _matched(status[-1]) - _matched(status[again - 1]) >= 3,
                          'scans matched again at the full range')
            # Stop: the setter goes back to 0.
            assert _reply(pose_i, 'stop') == 'ok stopped'
            watcher.until(lambda: watcher.events['pose/status'][-1].element[0] == 0, 'status: thread stopped')
            # Set the pose by hand 0.3 m and 5 degrees off the truth; the module starts from there
            # and brings the Pose back onto the truth.
            truth = watcher.events['PlutoBaseTruth'][-1].location
            # The module's Pose (setter 1) back on the truth after Poses it did not set (0 while
            # stopped, -1 as set by hand): a Pose of before the set, still on the truth, must not
            # pass for it.
            set_at = len(watcher.events[POSE])
            answer = _reply(pose_i, f'set {truth.x + 0.3} {truth.y - 0.1} {truth.theta + math.radians(5)}')
            assert answer.startswith('ok set'), answer
            watcher.until(lambda: any(p.cmd_flags != 1 for p in watcher.events[POSE][set_at:])
                          and watcher.events[POSE][-1].cmd_flags == 1 and _error_now(watcher)[0] < 0.05,
                          'the Pose back on the truth', timeout=60)
            assert re.match(r'ok pose \S+ \S+ \S+ setter 1 ', _reply(pose_i, 'pose'))
            pose_i.send('quit')
            assert pose_i.process.wait(timeout=30) == 0
    finally:
        watcher.close()


def test_a_bad_map_is_refused_with_file_line_and_reason(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path)
    bad = tmp_path / 'bad.xml'
    bad.write_text('<?xml version="1.0"?>\n<map name="x" version="1.0">\n'
                   '  <wall x1="0" y1="0" x2="0" y2="0"/>\n</map>\n')
    with module('pluto_nav', 'pose_module', directory, '-m', str(bad)) as process:
        assert process.process.wait(timeout=60) == 2
    assert f'{bad}:3:' in process.stderr
