"""The benchmark's metric (pluto_nav.slam_metric, slam_score): exact trajectories score zero, a
known error scores what it is, files are read as the benchmark writes them, bad files are refused
with file and line."""

from __future__ import annotations

import gzip
import math
import pathlib

import numpy as np
import pytest

from pluto_nav.geometry import compose, relative
from pluto_nav.slam_metric import (MetricError, load_relations, load_trajectory, relation_error,
                                   relative_pose_error, save_tum)
from pluto_nav.slam_score import main as slam_score


def _truth(n: int = 60) -> tuple[np.ndarray, np.ndarray]:
    poses = np.zeros((n, 3))
    for k in range(1, n):
        poses[k] = compose(poses[k - 1], (0.3, 0.0, 0.05))
    return 1000.0 + 0.5 * np.arange(n), poses


def _relations(stamps: np.ndarray, poses: np.ndarray, pairs: list[tuple[int, int]]) -> np.ndarray:
    rows = []
    for i, j in pairs:
        d = relative(poses[i], poses[j])
        rows.append((stamps[i], stamps[j], d[0], d[1], d[2]))
    return np.array(rows)


def test_the_truth_scores_zero_and_a_known_error_scores_what_it_is() -> None:
    stamps, truth = _truth()
    relations = _relations(stamps, truth, [(k, k + 1) for k in range(59)])
    exact = relation_error(stamps, truth, relations)
    assert exact.count == 59 and exact.missing == 0 and exact.translation < 1e-12 and exact.rotation_deg < 1e-9
    # Every step 2 cm longer and 0.5 degrees more turned than the truth.
    wrong = np.zeros_like(truth)
    for k in range(1, len(truth)):
        wrong[k] = compose(wrong[k - 1], (0.32, 0.0, 0.05 + math.radians(0.5)))
    score = relation_error(stamps, wrong, relations)
    assert score.translation == pytest.approx(0.02, abs=1e-9) and score.rotation_deg == pytest.approx(0.5)
    # A relation whose time is not a scan of the trajectory is counted, not scored.
    extra = np.vstack([relations, [[5.0, 6.0, 1.0, 0.0, 0.0]]])
    assert relation_error(stamps, truth, extra).missing == 1


def test_relative_pose_error_takes_the_pairs_0_3_to_2_metres_apart() -> None:
    stamps, truth = _truth()
    score = relative_pose_error(stamps, truth, stamps, truth)
    assert score.count > 100 and score.translation < 1e-12
    shifted = truth + np.array([5.0, -3.0, 0.0])            # a constant offset changes no relative pose
    assert relative_pose_error(stamps, shifted, stamps, truth).translation < 1e-9


def test_files_round_trip_and_a_graph_log_is_a_reference(tmp_path: pathlib.Path) -> None:
    stamps, truth = _truth()
    save_tum(tmp_path / 'traj.tum', stamps, truth)
    loaded_stamps, loaded = load_trajectory(tmp_path / 'traj.tum')
    assert np.allclose(loaded_stamps, stamps) and np.allclose(loaded, truth, atol=1e-6)
    lines = []
    for k, (t, (x, y, theta)) in enumerate(zip(stamps, truth)):
        lines.append(f'VERTEX2 {k} {x} {y} {theta}')
        lines.append(f'ROBOTLASER1 0 -1.57 3.14 0.0087 50 0.1 0 2 1.0 1.0 0 0 0 0 0 0 0 0 0 0 0 0 {t} host 0.0')
    with gzip.open(tmp_path / 'ref.graph.log.gz', 'wt') as out:
        out.write('\n'.join(lines) + '\n')
    ref_stamps, ref = load_trajectory(tmp_path / 'ref.graph.log.gz')
    assert np.allclose(ref_stamps, stamps) and np.allclose(ref, truth)
    rel = _relations(stamps, truth, [(0, 10), (5, 50)])
    with open(tmp_path / 'r.relations', 'w') as out:
        for t1, t2, dx, dy, dyaw in rel:
            out.write(f'{t1:.6f} {t2:.6f} {dx} {dy} 0 0 0 {dyaw}\n')
    assert np.allclose(load_relations(tmp_path / 'r.relations'), rel)


def test_slam_score_prints_the_score_and_refuses_bad_files(tmp_path: pathlib.Path, capsys) -> None:
    stamps, truth = _truth()
    save_tum(tmp_path / 'traj.tum', stamps, truth)
    with open(tmp_path / 'r.relations', 'w') as out:
        d = relative(truth[3], truth[4])
        out.write(f'{stamps[3]:.6f} {stamps[4]:.6f} {d[0]} {d[1]} 0 0 0 {d[2]}\n')
    assert slam_score([str(tmp_path / 'traj.tum'), str(tmp_path / 'r.relations')]) == 0
    assert '1 pairs: translation 0.0000 m' in capsys.readouterr().out
    (tmp_path / 'bad.relations').write_text('1 2 3 x 5 6 7 8\n')
    assert slam_score([str(tmp_path / 'traj.tum'), str(tmp_path / 'bad.relations')]) == 2
    assert 'bad.relations:1: not a number' in capsys.readouterr().err
    with pytest.raises(MetricError, match='cannot be read'):
        load_relations(tmp_path / 'missing')
