"""The localModule's resume file (read and write) and dead reckoning resumed from it, no ROS."""

from __future__ import annotations

import json
import math
import pathlib

import numpy as np
import pytest

from pluto_nav.dead_reckoning import RESUME_DMU_WAIT_S, DeadReckoning
from pluto_nav.geometry import compose, relative
from pluto_nav.odometry_model import increment_covariance
from pluto_nav.resume import ResumeState, read_resume, to_json, write_resume

COV = np.array([[0.01, 0.002, 0.0], [0.002, 0.02, 0.001], [0.0, 0.001, 0.003]])


def _state(pose_covariance: np.ndarray | None = COV * 2,
           dmu: tuple[float, float, float] | None = (12.7, 0.0, 0.01)) -> ResumeState:
    return ResumeState(odometry_stamp=1764718000.125, odometry=(1.5, -0.25, 0.3),
                       dead_reckoning=(4.4, 7.9, 0.31), dead_reckoning_covariance=COV,
                       pose=(4.5, 7.8, -3.1), pose_covariance=pose_covariance, setter=1, holder='poseModule',
                       odometry_sequence=812, odometry_session=2 ** 63 - 1,
                       dmu=dmu, dmu_session=815 if dmu else 0, dmu_sequence=4050 if dmu else 0)


def _same(a: ResumeState, b: ResumeState) -> None:
    assert (a.odometry_stamp, a.odometry, a.dead_reckoning, a.pose, a.setter, a.holder, a.odometry_sequence,
            a.odometry_session, a.dmu, a.dmu_session, a.dmu_sequence) == (
        b.odometry_stamp, b.odometry, b.dead_reckoning, b.pose, b.setter, b.holder, b.odometry_sequence,
        b.odometry_session, b.dmu, b.dmu_session, b.dmu_sequence)
    np.testing.assert_array_equal(a.dead_reckoning_covariance, b.dead_reckoning_covariance)
    if a.pose_covariance is None:
        assert b.pose_covariance is None
    else:
        np.testing.assert_array_equal(a.pose_covariance, b.pose_covariance)


@pytest.mark.parametrize('pose_covariance, dmu', [(COV * 2, (12.7, 0.0, 0.01)), (None, None)])
def test_a_resume_file_reads_back_what_was_written(tmp_path: pathlib.Path, pose_covariance, dmu) -> None:
    path = tmp_path / 'localModule.resume'
    state = _state(pose_covariance, dmu)
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
    assert changed('dmu', 'theta', 'north') == "dmu.theta: not a number ('north')"
    assert changed('dmu', 'session', -1) == 'dmu.session: not a count (-1)'
    assert changed(None, 'dmu', [1, 2]) == '"dmu" is not an object'
    without = json.loads(whole)
    del without['dmu']                 # a file of before the DMU was kept reads as one without a DMU
    path = tmp_path / 'older.resume'
    path.write_text(json.dumps(without))
    assert read_resume(path)[0].dmu is None
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


@pytest.mark.parametrize('turn', [2.5, 4.0, -3.6])
def test_a_resumed_dead_reckoning_takes_the_gap_s_turn_from_the_dmu_that_ran_on(turn: float) -> None:
    """The robot turned ``turn`` rad while no localModule ran; the odometry counts 5 % more, the DMU
    (the same process: its integrated heading, wrapped to one turn as it reports it) the turn
    itself: the resumed heading is the DMU's, beyond half a turn too (the turn nearest the
    odometry's); without the saved DMU reading it is the odometry's."""
    saved_odo = np.array([1.0, 2.0, 0.5])
    now_odo = compose(saved_odo, (0.0, 0.0, 1.05 * turn))
    saved_dmu = 7.0                                          # unwrapped, as the old process had it

    def resumed(dmu: tuple[float, float, float] | None) -> DeadReckoning:
        dr = DeadReckoning((4.0, 7.0, 1.0), resume_odometry=(100.0, tuple(saved_odo)), resume_dmu=dmu)
        raw = math.remainder(saved_dmu + turn, math.tau)    # what the DMU reports now
        dr.add_dmu(102.9, raw, 0.0, 0.0)
        dr.add_dmu(103.1, raw, 0.0, 0.0)
        dr.add_odometry(103.0, *now_odo)
        return dr

    with_dmu = resumed((saved_dmu, 0.0, 0.0))
    assert with_dmu.latest.dmu_used
    assert with_dmu.latest.pose[2] == pytest.approx(math.remainder(1.0 + turn, math.tau), abs=1e-9)
    without = resumed(None)
    assert without.latest.pose[2] == pytest.approx(math.remainder(1.0 + 1.05 * turn, math.tau), abs=1e-9)


def test_a_resumed_first_odometry_sample_waits_a_while_for_the_dmu_that_ran_on() -> None:
    """Its odometry came first (the DMU's subscription matched later): the sample waits for the
    DMU, whose turn it then takes; a DMU that does not come within RESUME_DMU_WAIT_S leaves the
    gap to the odometry."""
    saved_odo = np.array([1.0, 2.0, 0.5])
    now_odo = compose(saved_odo, (0.0, 0.0, 1.05))             # 1 rad turned, the odometry 5 % over
    wall = [50.0]
    dr = DeadReckoning((4.0, 7.0, 1.0), resume_odometry=(100.0, tuple(saved_odo)), resume_dmu=(7.0, 0.0, 0.0),
                       clock=lambda: wall[0])
    assert dr.add_odometry(103.0, *now_odo) == []
    wall[0] += 0.5
    assert dr.add_odometry(103.1, *now_odo) == []
    assert dr.add_dmu(102.9, math.remainder(8.0, math.tau), 0.0, 0.0) == []    # covers neither yet
    done = dr.add_dmu(103.2, math.remainder(8.0, math.tau), 0.0, 0.0)
    assert [s.stamp for s in done] == [103.0, 103.1] and done[0].dmu_used
    assert done[0].pose[2] == pytest.approx(2.0)
    late = DeadReckoning((4.0, 7.0, 1.0), resume_odometry=(100.0, tuple(saved_odo)), resume_dmu=(7.0, 0.0, 0.0),
                         clock=lambda: wall[0])
    assert late.add_odometry(103.0, *now_odo) == []
    wall[0] += RESUME_DMU_WAIT_S
    [first] = late.add_odometry(103.1, *now_odo)[:1]
    assert not first.dmu_used and first.pose[2] == pytest.approx(2.05)


def test_the_dmu_reading_kept_for_a_resume_is_in_the_dmu_s_own_terms() -> None:
    """After a restart of the DMU (its count from zero again) dead reckoning's own unwrapped
    heading goes on from where the old DMU left it; the reading kept for a resume is what the new
    DMU reports, so a resumed process that hears the same DMU report the same heading turns
    nothing (it once turned a robot that stood still by 138 degrees)."""
    dr = DeadReckoning((0.0, 0.0, 0.0))
    dr.add_dmu(10.0, 0.0, 0.0, 0.0)
    dr.add_odometry(10.05, 0.0, 0.0, 0.0)
    dr.add_dmu(10.1, 2.4, 0.0, 0.0)                       # turned 2.4 rad
    dr.add_dmu(11.0, 0.0, 0.0, 0.0, restarted=True)       # a new DMU counts from zero
    dr.add_dmu(11.1, 0.3, 0.0, 0.0)
    dr.add_dmu(11.3, 0.3, 0.0, 0.0)
    dr.add_odometry(11.2, 0.0, 0.0, 0.3)
    kept = dr.dmu_at(11.2)
    assert kept is not None and kept[0] == pytest.approx(0.3)
    resumed = DeadReckoning((0.0, 0.0, 0.3), resume_odometry=(11.2, (0.0, 0.0, 0.3)), resume_dmu=kept)
    resumed.add_dmu(14.0, 0.3, 0.0, 0.0)
    resumed.add_dmu(14.2, 0.3, 0.0, 0.0)
    [sample] = resumed.add_odometry(14.1, 0.0, 0.0, 0.3)
    assert sample.dmu_used and sample.pose[2] == pytest.approx(0.3, abs=1e-9)
