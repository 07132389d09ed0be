"""The localModule's resume file (read and write) and dead reckoning resumed from it, no ROS."""

from __future__ import annotations

import json
import math
import pathlib

import numpy as np
import pytest

from pluto_nav.dead_reckoning import DeadReckoning
from pluto_nav.geometry import compose, relative
from pluto_nav.odometry_model import increment_covariance
from pluto_nav.resume import ResumeState, read_resume, to_json, write_resume

COV = np.array([[0.01, 0.002, 0.0], [0.002, 0.02, 0.001], [0.0, 0.001, 0.003]])


def _state(pose_covariance: np.ndarray | None = COV * 2) -> ResumeState:
    return ResumeState(odometry_stamp=1764718000.125, odometry=(1.5, -0.25, 0.3),
                       dead_reckoning=(4.4, 7.9, 0.31), dead_reckoning_covariance=COV,
                       pose=(4.5, 7.8, -3.1), pose_covariance=pose_covariance, setter=1, holder='poseModule',
                       odometry_sequence=812, odometry_session=2 ** 63 - 1)


def _same(a: ResumeState, b: ResumeState) -> None:
    assert (a.odometry_stamp, a.odometry, a.dead_reckoning, a.pose, a.setter, a.holder, a.odometry_sequence,
            a.odometry_session) == (b.odometry_stamp, b.odometry, b.dead_reckoning, b.pose, b.setter, b.holder,
                                    b.odometry_sequence, b.odometry_session)
    np.testing.assert_array_equal(a.dead_reckoning_covariance, b.dead_reckoning_covariance)
    if a.pose_covariance is None:
        assert b.pose_covariance is None
    else:
        np.testing.assert_array_equal(a.pose_covariance, b.pose_covariance)


@pytest.mark.parametrize('pose_covariance', [COV * 2, None])
def test_a_resume_file_reads_back_what_was_written(tmp_path: pathlib.Path, pose_covariance) -> None:
    path = tmp_path / 'localModule.resume'
    state = _state(pose_covariance)
    write_resume(path, state)
    read, reason = read_resume(path)
    assert reason == '' and read is not None
    _same(state, read)                 # exact: JSON keeps a float's repr
    assert [p.name for p in tmp_path.iterdir()] == ['localModule.resume']     # no temporary left
    write_resume(path, _state(None))   # written over
    assert read_resume(path)[0].pose_covariance is None


def _refused(tmp_path: pathlib.Path, text: str | bytes) -> str:
    path = tmp_path / 'localModule.resume'
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    state, reason = read_resume(path)
    assert state is None and reason
    return reason


def test_a_truncated_or_wrong_resume_file_is_refused_with_a_reason(tmp_path: pathlib.Path) -> None:
    whole = to_json(_state())
    for cut in (1, len(whole) // 3, len(whole) // 2, len(whole) - 3):
        assert 'not JSON (truncated?)' in _refused(tmp_path, whole[:cut])
    assert 'not JSON' in _refused(tmp_path, '')
    assert _refused(tmp_path, b'\xff\xfe\x00garbage') == 'not a text file'
    assert _refused(tmp_path, '[1, 2, 3]') == 'not a JSON object'
    assert 'format' in _refused(tmp_path, '{"x": 1}')
    document = json.loads(whole)

    def changed(section: str | None, key: str, value: object) -> str:
        copy = json.loads(whole)
        (copy if section is None else copy[section])[key] = value
        return _refused(tmp_path, json.dumps(copy))

    assert 'version 2' in changed(None, 'version', 2)
    assert changed('odometry', 'x', 'one') == "odometry.x: not a number ('one')"
    assert changed('dead_reckoning', 'theta', math.inf) == 'dead_reckoning.theta: not finite'
    assert changed('pose', 'y', None) == 'pose.y: not a number (None)'
    assert 'dead_reckoning.covariance: not a list of 9 numbers' == changed('dead_reckoning', 'covariance', [1.0] * 8)
    assert 'not a covariance' in changed('dead_reckoning', 'covariance', [1, 0, 0, 0, -1, 0, 0, 0, 1])
    assert 'not a covariance' in changed('pose', 'covariance', [1, 0.5, 0, 0, 1, 0, 0, 0, 1])
    assert changed('pose', 'setter', 1.5) == 'pose.setter: not an integer (1.5)'
    assert changed(None, 'odometry', [1, 2]) == 'no "odometry" object'
    assert read_resume(tmp_path / 'nowhere.resume') == (None, 'no such file')
    directory = tmp_path / 'a-directory.resume'
    directory.mkdir()
    state, reason = read_resume(directory)
    assert state is None and reason.startswith('cannot read it')
    assert document['format'] == 'pluto_nav.resume'


def test_resumed_dead_reckoning_applies_the_motion_made_since_the_saved_reading() -> None:
    saved_odo = np.array([1.0, 2.0, 0.5])
    now_odo = compose(saved_odo, (0.8, 0.1, 0.4))          # the base moved on while nobody listened
    dr = DeadReckoning((4.0, 7.0, 1.0), start_covariance=COV, resume_odometry=(100.0, tuple(saved_odo)))
    assert dr.latest is None and dr.latest_odometry is None
    [first] = dr.add_odometry(102.0, *now_odo)
    np.testing.assert_allclose(first.pose, compose((4.0, 7.0, 1.0), relative(saved_odo, now_odo)), atol=1e-12)
    assert np.all(np.diag(first.covariance) > np.diag(COV))      # grown from the saved one
    assert dr.odometry_resets == 0
    stamp, odo = dr.latest_odometry
    assert stamp == 102.0 and tuple(odo) == pytest.approx(tuple(now_odo))
    # The base restarted too: its odometry counts from zero again, a jump no robot makes: no motion.
    jumped = DeadReckoning((4.0, 7.0, 1.0), start_covariance=COV, resume_odometry=(100.0, (30.0, 2.0, 0.5)))
    [first] = jumped.add_odometry(101.0, 0.0, 0.0, 0.0)
    np.testing.assert_allclose(first.pose, (4.0, 7.0, 1.0))
    assert jumped.odometry_resets == 1
    # A start that is not a resume: the first sample is the start, whatever the odometry reads.
    fresh = DeadReckoning((4.0, 7.0, 1.0))
    [first] = fresh.add_odometry(101.0, *now_odo)
    np.testing.assert_allclose(first.pose, (4.0, 7.0, 1.0))


def test_a_resumed_dead_reckoning_s_first_scan_increment_spans_the_gap_with_its_covariance() -> None:
    """The restarted localModule's first laser increment goes from the saved reading, and its
    covariance is the gap's odometry's (a turn of 0.6 rad with no DMU: heading sigma 0.05 per
    radian and 0.02 per metre), not zero; once the history no longer reaches back, None."""
    saved_odo = np.array([1.0, 2.0, 0.5])
    gap = (0.8, 0.1, 0.6)
    wall = [0.0]
    dr = DeadReckoning((4.0, 7.0, 1.0), start_covariance=COV, resume_odometry=(100.0, tuple(saved_odo)),
                       clock=lambda: wall[0])
    dr.add_odometry(102.0, *compose(saved_odo, gap))
    dr.add_odometry(102.1, *compose(saved_odo, compose(gap, (0.05, 0.0, 0.0))))
    increment, covariance = dr.increment_since_start(102.05)
    np.testing.assert_allclose(increment, compose(gap, (0.025, 0.0, 0.0)), atol=1e-9)
    expected = increment_covariance(np.array(gap))
    assert math.sqrt(covariance[2, 2]) == pytest.approx(math.sqrt(expected[2, 2]), rel=0.01)
    assert math.sqrt(covariance[2, 2]) > 0.05 * 0.6
    assert dr.increment_since_start(99.0) is None and dr.increment_since_start(103.0) is None
    for k in range(1, 80):                                   # 8 s on: the history is trimmed
        wall[0] += 0.1
        dr.add_odometry(102.1 + 0.1 * k, *compose(saved_odo, compose(gap, (0.05 + 0.01 * k, 0.0, 0.0))))
    assert dr.increment_since_start(dr.latest.stamp) is None
