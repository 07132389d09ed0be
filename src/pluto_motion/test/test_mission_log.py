"""The mission's figures (pluto_motion.mission_log): clearance to walls, contacts counted once per
touch, distance along the truth, pose RMSE against it; and the plot is a PNG."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest

from pluto_motion.mission_log import Goal, MissionLog, Sample, wall_clearance
from pluto_motion.mission_plot import plot_mission

WALLS = [(0.0, 0.0, 10.0, 0.0), (0.0, 0.0, 0.0, 4.0)]


def _sample(t: float, truth: tuple[float, float], error: float = 0.0) -> Sample:
    return Sample(t, (truth[0] + error, truth[1], 0.0), np.diag([0.01, 0.01, 0.001]), (truth[0], truth[1], 0.0),
                  (truth[0], truth[1], 0.0))


def test_clearance_is_the_distance_to_the_nearest_segment() -> None:
    walls = np.array(WALLS)
    assert wall_clearance(walls, 5.0, 2.0) == pytest.approx(2.0)
    assert wall_clearance(walls, 1.0, 0.5) == pytest.approx(0.5)
    assert wall_clearance(walls, 12.0, 0.0) == pytest.approx(2.0)       # beyond the segment's end
    assert wall_clearance(np.zeros((0, 4)), 1.0, 1.0) == math.inf


def test_contacts_are_counted_once_per_touch_and_the_figures_follow_the_truth() -> None:
    log = MissionLog(WALLS, radius=0.35)
    path = [(5.0, 2.0), (5.0, 1.0), (5.0, 0.3), (5.0, 0.2), (5.0, 1.0), (5.0, 0.1), (5.0, 2.0)]
    for i, point in enumerate(path):
        log.add(_sample(float(i), point, error=0.1 if i % 2 else 0.0))
    log.goals = [Goal('a', 5.0, 2.0, 0.0, 3.0, 'reached'), Goal('b', 5.0, 0.1, 3.0, 6.0, 'timed out')]
    s = log.summary()
    assert s.contacts == 2                          # two separate touches (0.3/0.2 and 0.1)
    assert s.clearance == pytest.approx(0.1)
    assert s.distance == pytest.approx(1.0 + 0.7 + 0.1 + 0.8 + 0.9 + 1.9)
    assert s.pose_rmse == pytest.approx(math.sqrt(3 * 0.01 / 7)) and s.pose_max == pytest.approx(0.1)
    assert (s.goals, s.reached, s.seconds) == (2, 1, 6.0)


def test_without_a_truth_contacts_are_unknown(tmp_path: pathlib.Path) -> None:
    log = MissionLog(WALLS, radius=0.35)
    for i in range(30):
        log.add(Sample(float(i), (1.0 + 0.2 * i, 2.0, 0.0), np.diag([0.04, 0.02, 0.001]), None, None))
    s = log.summary()
    assert s.contacts == -1 and math.isnan(s.pose_rmse) and s.distance == pytest.approx(5.8)
    log.last_scan = np.array([[7.0, y] for y in np.linspace(0.5, 3.5, 50)])   # a wall seen at the end
    plot_mission(log, tmp_path / 'm.png')
    assert (tmp_path / 'm.png').read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'


def test_a_pose_that_stopped_coming_is_not_compared_with_where_the_robot_went() -> None:
    log = MissionLog(WALLS, radius=0.35)
    log.add(_sample(0.0, (5.0, 2.0), error=0.05))
    # The localModule is stopped: its last pose is sampled on while the robot drives 1 m on; the
    # truth of that pose's stamp is no longer kept (None), the truth now still counts contacts.
    for i in range(1, 11):
        log.add(Sample(float(i), (5.05, 2.0, 0.0), np.eye(3), (5.0, 2.0 - 0.19 * i, 0.0), None))
    s = log.summary()
    assert s.pose_max == pytest.approx(0.05)
    assert s.contacts == 1 and s.clearance == pytest.approx(0.1)
