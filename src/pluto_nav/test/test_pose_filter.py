"""The pose EKF: prediction, correction from simulator scans, outliers, SPD covariance."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from random_maps import random_map
from test_matching import MOUNT, SIGMA, scans, wall_hit
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.world import World

from pluto_nav.geometry import compose, compose_jacobians, wrap
from pluto_nav.lines import extract_lines
from pluto_nav.pose_filter import COVARIANCE_FLOOR, PoseFilter
from pluto_nav.wall_map import WallMap

WORLD = random_map(301)
WALLS = WallMap(WORLD.walls)


def filter_at(pose, sigma_xy=0.02, sigma_theta=math.radians(1)):
    f = PoseFilter()
    f.set_pose(pose, np.diag([sigma_xy ** 2, sigma_xy ** 2, sigma_theta ** 2]))
    return f


def is_spd(m, floor=0.0):
    return np.array_equal(m, m.T) and np.linalg.eigvalsh(m)[0] > floor


def test_predict_composes_and_propagates():
    f = filter_at((1.0, 2.0, 0.5))
    p0 = f.covariance
    u, q = np.array([0.3, 0.05, 0.1]), np.diag([1e-4, 2e-5, 3e-5])
    f.predict(u, q)
    assert np.allclose(f.pose, compose((1.0, 2.0, 0.5), u))
    ja, ju = compose_jacobians((1.0, 2.0, 0.5), u)
    assert np.allclose(f.covariance, ja @ p0 @ ja.T + ju @ q @ ju.T)
    f.predict((0, 0, 0), np.zeros((3, 3)))            # standing still: zero noise is allowed
    assert is_spd(f.covariance)


def test_update_without_lines_or_matches_leaves_the_pose():
    f = filter_at((0.0, 0.0, 0.0))
    result = f.update([], WALLS)
    assert (result.matches, result.accepted, result.lines) == (0, False, 0)
    assert math.isnan(result.nis)
    assert np.allclose(f.pose, 0.0)


def test_scans_pull_a_wrong_prediction_to_the_truth():
    for truth, _, lines in scans(WORLD, 10, seed=8):
        if len(lines) < 3:
            continue                                  # one or two walls do not fix a pose
        off = compose(truth, (0.25, -0.2, math.radians(6)))
        f = filter_at(off, 0.3, math.radians(8))
        result = f.update(lines, WALLS)
        assert result.accepted and result.matches >= 2
        assert math.dist(f.pose[:2], truth[:2]) < 0.03
        assert abs(wrap(f.pose[2] - truth[2])) < math.radians(0.5)
        assert is_spd(f.covariance)
        assert np.all(np.diag(f.covariance) < 0.3 ** 2)   # it learned something


def cluttered(world, seed):
    """``world`` with unmapped boxes (0.8 m x 0.3 m) 0.15 m in front of its longer walls."""
    rng = np.random.default_rng(seed)
    extra = []
    for x1, y1, x2, y2 in world.walls:
        length = math.hypot(x2 - x1, y2 - y1)
        if length < 2.0:
            continue
        u = np.array([x2 - x1, y2 - y1]) / length
        n = np.array([-u[1], u[0]]) * rng.choice([-1.0, 1.0])
        centre = np.array([x1, y1]) + u * length * rng.uniform(0.3, 0.7) + n * 0.3
        corners = [centre + a * 0.4 * u + b * 0.15 * n for a, b in ((-1, -1), (1, -1), (1, 1),
                                                                      (-1, 1))]
        extra += [(*p, *q) for p, q in zip(corners, corners[1:] + corners[:1])]
    return World(np.vstack([world.walls, extra]), places=world.places)


def test_unmapped_furniture_in_front_of_walls_does_not_bend_the_pose():
    clutter = cluttered(WORLD, 4)
    rng = np.random.default_rng(2)
    worst, boxes = 0.0, 0
    for truth, ranges, lines in scans(clutter, 30, seed=9):
        if len(lines) < 3:
            continue                                  # one or two walls do not fix a pose
        boxes += sum(wall_hit(clutter, truth, ranges, line) >= len(WALLS) for line in lines)
        f = filter_at(compose(truth, (*rng.normal(0, 0.03, 2), rng.normal(0, 0.01))), 0.1, 0.05)
        f.update(lines, WALLS)
        worst = max(worst, math.dist(f.pose[:2], truth[:2]))
    assert boxes >= 5                                 # the laser saw the furniture
    assert worst < 0.03


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.floats(-0.3, 0.3), st.floats(-0.05, 0.05), st.floats(-0.5, 0.5),
                          st.floats(0.0, 0.1), st.integers(0, 2 ** 31)), min_size=1, max_size=8),
       st.floats(1e-3, 1.0))
def test_the_covariance_stays_symmetric_positive_definite(steps, start_sigma):
    """Whatever the increments and scans, even scans taken somewhere else entirely."""
    f = filter_at(WORLD.place('start'), start_sigma, start_sigma)
    laser = LaserModel(LaserGeometry(noise_sigma=0.01, mount_x=MOUNT[0]),
                       np.random.default_rng(0))
    box = WORLD.bounds
    for dx, dy, dtheta, noise, seed in steps:
        rng = np.random.default_rng(seed)
        q = rng.normal(0.0, noise, (3, 3))
        f.predict((dx, dy, dtheta), q @ q.T)
        assert is_spd(f.covariance)
        x, y = rng.uniform((box.xmin, box.ymin), (box.xmax, box.ymax))
        ranges = laser.scan(WORLD, x, y, rng.uniform(-math.pi, math.pi))
        result = f.update(extract_lines(ranges, range_sigma=SIGMA), WALLS)
        assert is_spd(f.covariance, COVARIANCE_FLOOR * 0.999 if result.accepted else 0.0)
        assert np.all(np.isfinite(f.pose)) and -math.pi < f.pose[2] <= math.pi
        assert result.accepted == (result.matches > 0)


@pytest.mark.parametrize('call', [
    lambda f: f.set_pose((0, 0, math.nan), np.eye(3)),
    lambda f: f.set_pose((0, 0, 0), np.diag([1.0, 1.0, 0.0])),
    lambda f: f.set_pose((0, 0, 0), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]),
    lambda f: f.predict((0, 0, 0), -np.eye(3)),
    lambda f: f.predict((math.inf, 0, 0), np.eye(3)),
])
def test_bad_input_is_refused(call):
    with pytest.raises(ValueError):
        call(PoseFilter())
