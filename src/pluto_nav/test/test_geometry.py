"""SE(2) algebra, line transforms and their Jacobians (against numeric differentiation)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from pluto_nav.geometry import (
    compose,
    compose_jacobians,
    inverse,
    inverse_jacobian,
    line_to_frame,
    line_to_frame_jacobian,
    relative,
    relative_jacobians,
    transform_points,
    wrap,
)

coordinate = st.floats(-50.0, 50.0)
angle = st.floats(-10.0, 10.0)
poses = st.tuples(coordinate, coordinate, angle).map(np.array)


def numeric_jacobian(f, x, eps=1e-6):
    """Central differences of ``f`` (vector out) at ``x``; angle outputs differenced wrapped."""
    x = np.asarray(x, dtype=float)
    columns = []
    for k in range(len(x)):
        step = np.zeros_like(x)
        step[k] = eps
        diff = np.asarray(f(x + step), dtype=float) - np.asarray(f(x - step), dtype=float)
        columns.append(diff / (2 * eps))
    return np.column_stack(columns)


def assert_pose_close(a, b, tol=1e-9):
    assert abs(a[0] - b[0]) < tol and abs(a[1] - b[1]) < tol
    assert abs(wrap(a[2] - b[2])) < tol


@settings(deadline=None)
@given(st.floats(-1e4, 1e4))
def test_wrap_is_in_half_open_interval_and_keeps_the_direction(a):
    w = wrap(a)
    assert -math.pi < w <= math.pi
    assert math.isclose(math.cos(w), math.cos(a), abs_tol=1e-9)
    assert math.isclose(math.sin(w), math.sin(a), abs_tol=1e-9)


def test_wrap_maps_minus_pi_to_pi_and_works_on_arrays():
    assert wrap(-math.pi) == math.pi
    assert wrap(math.pi) == math.pi
    out = wrap(np.array([-math.pi, 3 * math.pi, 0.5, -7.0]))
    assert isinstance(out, np.ndarray)
    assert np.allclose(out, [math.pi, math.pi, 0.5, -7.0 + 2 * math.pi])


@settings(deadline=None)
@given(poses, poses)
def test_compose_inverse_and_relative_agree(a, b):
    assert_pose_close(compose(a, inverse(a)), (0.0, 0.0, 0.0), 1e-9)
    assert_pose_close(relative(a, compose(a, b)), b, 1e-8)
    assert_pose_close(compose(inverse(a), b), relative(a, b), 1e-8)
    assert -math.pi < compose(a, b)[2] <= math.pi


@settings(max_examples=100, deadline=None)
@given(poses, poses)
def test_compose_jacobians_match_numeric(a, b):
    ja, jb = compose_jacobians(a, b)
    assert np.allclose(ja, numeric_jacobian(lambda p: _unwrapped_compose(p, b), a), atol=1e-5)
    assert np.allclose(jb, numeric_jacobian(lambda p: _unwrapped_compose(a, p), b), atol=1e-5)


@settings(max_examples=100, deadline=None)
@given(poses)
def test_inverse_jacobian_matches_numeric(a):
    def unwrapped(p):
        out = inverse(p)
        out[2] = -p[2]
        return out
    assert np.allclose(inverse_jacobian(a), numeric_jacobian(unwrapped, a), atol=1e-5)


@settings(max_examples=100, deadline=None)
@given(poses, poses)
def test_relative_jacobians_match_numeric(a, b):
    def unwrapped(p, q):
        out = relative(p, q)
        out[2] = q[2] - p[2]
        return out
    ja, jb = relative_jacobians(a, b)
    assert np.allclose(ja, numeric_jacobian(lambda p: unwrapped(p, b), a), atol=1e-5)
    assert np.allclose(jb, numeric_jacobian(lambda q: unwrapped(a, q), b), atol=1e-5)


def _unwrapped_compose(a, b):
    out = compose(a, b)
    out[2] = a[2] + b[2]
    return out


@settings(deadline=None)
@given(poses, st.floats(-math.pi, math.pi), st.floats(0.0, 60.0), st.floats(-20.0, 20.0))
def test_line_to_frame_keeps_the_points_of_the_line(pose, gamma, rho, t):
    # A point of the map line, seen from the sensor, lies on the transformed line.
    point = rho * np.array([math.cos(gamma), math.sin(gamma)]) + \
        t * np.array([-math.sin(gamma), math.cos(gamma)])
    local = transform_points(inverse(pose), point)[0]
    g, r = line_to_frame(gamma, rho, pose)
    assert r >= 0.0
    assert -math.pi < float(g) <= math.pi
    assert abs(local[0] * math.cos(g) + local[1] * math.sin(g) - r) < 1e-7 * (1 + rho + abs(t))


@settings(max_examples=100, deadline=None)
@given(poses, st.floats(-math.pi, math.pi), st.floats(0.0, 60.0))
def test_line_to_frame_jacobian_matches_numeric_on_both_sides(pose, gamma, rho):
    g, r = line_to_frame(gamma, rho, pose)
    assume(float(r) > 1e-3)                       # away from the flip, where it has no derivative
    jac = line_to_frame_jacobian(gamma, rho, pose)[0]

    def h(p):
        g2, r2 = line_to_frame(gamma, rho, p)
        return np.array([float(g) + wrap(float(g2) - float(g)), float(r2)])
    assert np.allclose(jac, numeric_jacobian(h, pose), atol=1e-5)


def test_line_to_frame_flips_when_the_sensor_is_beyond_the_line():
    # The wall x = 2 (gamma 0, rho 2) seen from x = 5 facing +x: behind, at distance 3.
    g, r = line_to_frame(0.0, 2.0, (5.0, 0.0, 0.0))
    assert float(r) == pytest.approx(3.0)
    assert abs(float(g)) == pytest.approx(math.pi)
    jac = line_to_frame_jacobian(0.0, 2.0, (5.0, 0.0, 0.0))[0]
    assert np.allclose(jac, [[0, 0, -1], [1, 0, 0]])
    jac = line_to_frame_jacobian(0.0, 2.0, (0.0, 0.0, 0.0))[0]
    assert np.allclose(jac, [[0, 0, -1], [-1, 0, 0]])


def test_line_functions_are_vectorised():
    gamma = np.array([0.0, math.pi / 2, -2.0])
    rho = np.array([1.0, 2.0, 3.0])
    g, r = line_to_frame(gamma, rho, (0.1, 0.2, 0.3))
    assert g.shape == r.shape == (3,)
    assert line_to_frame_jacobian(gamma, rho, (0.1, 0.2, 0.3)).shape == (3, 2, 3)
