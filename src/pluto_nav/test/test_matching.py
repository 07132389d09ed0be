"""Matching observed lines to map walls: simulator scans, thin walls, collinear walls, ambiguity."""

import math
import pathlib

import numpy as np
import pytest
from random_maps import random_map
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.mapfile import load_map

from pluto_nav.geometry import compose, line_to_frame, line_to_frame_jacobian, wrap
from pluto_nav.lines import LineFeature, extract_lines
from pluto_nav.matching import MatchSettings, match_lines
from pluto_nav.wall_map import WallMap

MAPS = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'
MOUNT = (0.2, 0.0, 0.0)
SIGMA = math.hypot(0.01, 0.01 / math.sqrt(12))


def scans(world, count, seed):
    """``(true laser pose, lines)`` from ``count`` free poses of ``world``."""
    rng = np.random.default_rng(seed)
    laser = LaserModel(LaserGeometry(noise_sigma=0.01, mount_x=MOUNT[0]), rng)
    box = world.bounds
    out = []
    while len(out) < count:
        x, y = rng.uniform((box.xmin, box.ymin), (box.xmax, box.ymax))
        if not world.is_free((x, y), 0.5):
            continue
        theta = rng.uniform(-math.pi, math.pi)
        ranges = laser.scan(world, x, y, theta)
        lines = extract_lines(ranges, range_sigma=SIGMA)
        out.append((compose((x, y, theta), MOUNT), ranges, lines))
    return out


def wall_hit(world, pose, ranges, line):
    """The wall most of the line's beams hit (nearest wall to each beam's end point)."""
    beams = np.arange(line.first, line.last + 1)
    phi = -math.pi / 2 + math.pi / (len(ranges) - 1) * beams
    r = ranges[beams]
    x = pose[0] + r * np.cos(pose[2] + phi)
    y = pose[1] + r * np.sin(pose[2] + phi)
    hits = [world.nearest_wall((a, b))[2] for a, b in zip(x, y) if np.isfinite(a)]
    return int(np.bincount(hits).argmax())


def worlds():
    return [load_map(MAPS / 'office.xml'), random_map(101), random_map(102)]


@pytest.mark.parametrize('world', worlds(), ids=lambda w: w.name)
def test_lines_of_simulated_scans_match_the_walls_their_beams_hit(world):
    walls = WallMap(world.walls)
    small = np.diag([0.02 ** 2, 0.02 ** 2, math.radians(1) ** 2])
    total = matched = 0
    for pose, ranges, lines in scans(world, 15, seed=3):
        result = match_lines(lines, walls, pose, small)
        total += len(lines)
        matched += len(result.matches)
        for match in result.matches:
            truth = wall_hit(world, pose, ranges, lines[match.line])
            assert walls.line[match.wall] == walls.line[truth], (pose, match)
            assert not match.fallback
    assert matched >= 0.9 * total


@pytest.mark.parametrize('world', worlds(), ids=lambda w: w.name)
def test_a_poor_prediction_matches_fewer_lines_but_none_wrongly(world):
    walls = WallMap(world.walls)
    wide = np.diag([0.3 ** 2, 0.3 ** 2, math.radians(6) ** 2])
    rng = np.random.default_rng(5)
    matched = 0
    for pose, ranges, lines in scans(world, 15, seed=4):
        guess = pose + np.array([*rng.normal(0.0, 0.2, 2), rng.normal(0.0, math.radians(4))])
        result = match_lines(lines, walls, guess, wide)
        matched += len(result.matches)
        for match in result.matches:
            truth = wall_hit(world, pose, ranges, lines[match.line])
            assert walls.line[match.wall] == walls.line[truth], (pose, guess, match)
    assert matched > 0


def feature(gamma, rho, start, end, sigma=(0.002, 0.005)):
    start, end = np.array(start, float), np.array(end, float)
    return LineFeature(gamma=gamma, rho=rho, covariance=np.diag(np.square(sigma)), points=50,
                       first=0, last=49, start=start, end=end,
                       length=float(np.linalg.norm(end - start)))


LEFT = feature(math.pi / 2, 2.0, (-1.0, 2.0), (1.0, 2.0))       # a wall 2 m to the laser's left


def test_the_near_face_of_a_thin_wall_hides_the_far_one():
    # A wall 0.12 m thick: faces y = 2 and y = 2.12, caps at x = +-3; laser at the origin.
    walls = WallMap([(-3, 2.12, 3, 2.12), (-3, 2, 3, 2), (-3, 2, -3, 2.12), (3, 2, 3, 2.12)])
    uncertain = np.diag([0.3 ** 2, 0.3 ** 2, 0.05 ** 2])
    result = match_lines([LEFT], walls, (0, 0, 0), uncertain)
    assert [m.wall for m in result.matches] == [1]
    # Seen from the other side the other face is the near one.
    behind = feature(-math.pi / 2, 1.88, (-1.0, -1.88), (1.0, -1.88))
    result = match_lines([behind], walls, (0, 4, 0), uncertain)
    assert [m.wall for m in result.matches] == [0]


def test_a_line_along_collinear_pieces_is_one_measurement():
    walls = WallMap([(-3, 2, -0.2, 2), (-0.2, 2, 3, 2)])     # one wall drawn in two pieces
    result = match_lines([LEFT], walls, (0, 0, 0), np.diag([0.01, 0.01, 0.001]))
    assert len(result.matches) == 1 and result.ambiguous == []
    assert result.matches[0].wall in (0, 1)


def test_two_different_walls_fitting_equally_are_ambiguous():
    # Two walls through (0, 2), 0.2 rad apart: a very uncertain heading cannot tell them apart.
    c, s = math.cos(0.2) * 3, math.sin(0.2) * 3
    walls = WallMap([(-3, 2, 3, 2), (-c, 2 - s, c, 2 + s)])
    result = match_lines([LEFT], walls, (0, 0, 0), np.diag([0.2 ** 2, 0.2 ** 2, 0.3 ** 2]))
    assert result.matches == [] and result.ambiguous == [0]
    # A confident heading settles it.
    result = match_lines([LEFT], walls, (0, 0, 0), np.diag([0.01, 0.01, 0.02 ** 2]))
    assert [m.wall for m in result.matches] == [0]


def test_a_long_line_is_not_a_short_wall_and_overlap_is_needed():
    walls = WallMap([(2.5, 2, 2.8, 2)])                     # 0.3 m, off to the side
    uncertain = np.diag([0.5 ** 2, 0.5 ** 2, 0.2 ** 2])
    assert match_lines([LEFT], walls, (0, 0, 0), uncertain).unmatched == [0]
    walls = WallMap([(3.5, 2, 9, 2)])                       # long enough, but not where it is seen
    assert match_lines([LEFT], walls, (0, 0, 0), np.diag([0.01, 0.01, 0.001])).unmatched == [0]


def test_a_match_carries_innovation_jacobian_and_covariances():
    walls = WallMap([(-3, 2, 3, 2), (4, -3, 4, 3)])
    pose = np.array([0.05, -0.03, 0.02])
    p = np.diag([0.01, 0.02, 0.003])
    result = match_lines([LEFT], walls, pose, p)
    (match,) = result.matches
    g, r = line_to_frame(walls.gamma[0], walls.rho[0], pose)
    assert match.innovation == pytest.approx([wrap(LEFT.gamma - float(g)), LEFT.rho - float(r)])
    h = line_to_frame_jacobian(walls.gamma[0], walls.rho[0], pose)[0]
    assert np.allclose(match.jacobian, h)
    assert np.allclose(match.innovation_covariance, h @ p @ h.T + LEFT.covariance)
    assert match.distance == pytest.approx(
        match.innovation @ np.linalg.solve(match.innovation_covariance, match.innovation))


def test_an_odometry_slip_is_caught_by_the_fallback_gate():
    walls = WallMap([(-3, 2, 3, 2)])
    p = np.diag([0.01 ** 2, 0.01 ** 2, 0.001 ** 2])
    slipped = (0.0, -0.04, 0.0)                             # 4 sigma off in y
    (match,) = match_lines([LEFT], walls, slipped, p).matches
    assert match.fallback
    assert match_lines([LEFT], walls, slipped, p,
                       MatchSettings(fallback_gate_probability=0.99)).unmatched == [0]


def test_nothing_to_match():
    walls = WallMap([(-3, 2, 3, 2)])
    assert match_lines([], walls, (0, 0, 0), np.eye(3)).matches == []
    behind = match_lines([LEFT], walls, (0, 0, math.pi), np.diag([0.01, 0.01, 0.001]))
    assert behind.unmatched == [0]


@pytest.mark.parametrize('kwargs', [{'gate_probability': 1.0}, {'min_coverage': 1.5},
                                    {'gate_probability': 0.999,
                                     'fallback_gate_probability': 0.99}])
def test_bad_settings_are_refused(kwargs):
    with pytest.raises(ValueError):
        MatchSettings(**kwargs)
