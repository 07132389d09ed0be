"""The SLAM line landmark model: predictions, Jacobians (against finite differences), and the
bookkeeping of extents whose ends are tied to neighbouring walls."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pluto_nav.landmark_extent import AnchorCandidates, End, Extent, choose_anchor, resolve
from pluto_nav.line_landmark import align, along, initialise, intersection, observe, point_at

# Laser poses on both sides of the test lines, and lines in both forms (rho of either sign).
POSES = [(1.0, -2.0, 0.3), (-3.0, 4.0, -2.5), (6.0, 1.0, 3.0)]
LINES = [(0.4, 2.0), (-2.0, -1.5), (3.0, 0.2)]


def _numeric(f, x: np.ndarray, step: float = 1e-6) -> np.ndarray:
    """Central differences of ``f`` (angle outputs first: wrapped) with respect to ``x``."""
    columns = []
    for i in range(len(x)):
        dx = np.zeros(len(x))
        dx[i] = step
        diff = f(x + dx) - f(x - dx)
        diff[0] = math.remainder(diff[0], 2.0 * math.pi)
        columns.append(diff / (2.0 * step))
    return np.array(columns).T


@pytest.mark.parametrize('pose', POSES)
@pytest.mark.parametrize('line', LINES)
def test_observe_jacobians(pose, line) -> None:
    pose, line = np.array(pose), np.array(line)
    z, h_pose, h_line, offset = observe(line, pose)
    assert z[0, 1] == pytest.approx(abs(offset[0]))
    np.testing.assert_allclose(h_pose[0], _numeric(lambda p: observe(line, p)[0][0], pose),
                               atol=1e-6)
    np.testing.assert_allclose(h_line[0], _numeric(lambda q: observe(q, pose)[0][0], line),
                               atol=1e-6)


@pytest.mark.parametrize('pose', POSES)
def test_initialise_inverts_observe(pose) -> None:
    pose = np.array(pose)
    z = np.array([0.7, 2.5])
    landmark, g_pose, g_z = initialise(z[0], z[1], pose)
    assert landmark[1] >= 0.0
    np.testing.assert_allclose(observe(landmark, pose)[0][0], z, atol=1e-12)
    np.testing.assert_allclose(g_pose, _numeric(lambda p: initialise(z[0], z[1], p)[0], pose),
                               atol=1e-6)
    np.testing.assert_allclose(g_z, _numeric(lambda q: initialise(q[0], q[1], pose)[0], z),
                               atol=1e-6)


def test_align_and_positions() -> None:
    line, sign = align((0.1, 3.0), (0.1 + math.pi, -3.0))
    assert sign == -1.0 and line == pytest.approx([0.1, 3.0])
    point = point_at(0.1, 3.0, 1.5)
    assert along(0.1, point) == pytest.approx(1.5)
    assert point @ np.array([math.cos(0.1), math.sin(0.1)]) == pytest.approx(3.0)
    t, sine = intersection(0.0, 2.0, math.pi / 2, 5.0)       # x = 2 meets y = 5
    assert t == pytest.approx(5.0) and sine == pytest.approx(1.0)


def _lines_of(table: dict[int, tuple[float, float]]):
    return lambda keys: np.array([table.get(int(k), (np.nan, np.nan)) for k in keys]).reshape(-1, 2)


def test_anchored_end_follows_its_anchor_and_a_free_end_stays_put() -> None:
    wall = np.array([math.pi / 2, 1.0])                        # y = 1, t along -x
    cross = (0.0, 4.0)                                          # x = 4 crosses it at t = -4
    candidates = AnchorCandidates(np.array([7]), np.array([cross]), np.array([[0.0, 3.0]]))
    near_cross = choose_anchor(wall, -3.9, candidates, exclude=0, radius=2.0, min_angle=0.5)
    free = choose_anchor(wall, 2.0, candidates, exclude=0, radius=0.5, min_angle=0.5)
    assert (near_cross.anchor, near_cross.offset) == (7, pytest.approx(0.1))
    assert free.anchor is None and free.point == pytest.approx((-2.0, 1.0))
    extent = Extent(near_cross, free)
    # The cross wall moves 0.3 m (a loop closure): the end near it moves with it.
    table = {7: (0.0, 4.3)}
    assert resolve([extent], wall[None], _lines_of(table))[0] == pytest.approx([-4.2, 2.0])
    # The wall turns by 0.01 rad about (1, 1): the free end, 3 m away, moves 3 cm at most,
    # not the 20 cm its t (measured from the origin's foot) would have taken it.
    turned = np.array([math.pi / 2 + 0.01, math.cos(0.01) + math.sin(0.01)])
    _, free_t = extent.interval(turned, _lines_of(table))
    assert np.linalg.norm(point_at(*turned, free_t) - np.array([-2.0, 1.0])) < 0.031
    # The anchor forgotten: the end stays where it last was.
    extent.interval(wall, _lines_of(table))
    extent.interval(wall, _lines_of({}))
    assert extent.lo.anchor is None
    assert extent.interval(wall, _lines_of({}))[0] == pytest.approx(-4.2)


def test_flipped_extent_is_the_same_segment() -> None:
    wall = np.array([0.3, 2.0])
    extent = Extent(End.at(wall, -1.0), End(5, 0.25, (0.0, 0.0), 0.0))
    table = {5: (0.3 + math.pi / 2, 1.0)}
    lo, hi = extent.interval(wall, _lines_of(table))
    other = np.array([0.3 + math.pi - 2 * math.pi, -2.0])
    flo, fhi = extent.flipped().interval(other, _lines_of(table))
    np.testing.assert_allclose(sorted([point_at(*wall, lo)[0], point_at(*wall, hi)[0]]),
                               sorted([point_at(*other, flo)[0], point_at(*other, fhi)[0]]),
                               atol=1e-12)
