"""Line extraction: fits of synthetic walls within their covariance, breaks, invalid scans."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from pluto_nav.lines import extract_lines, scan_points

BEAMS = 361
ANGLES = -math.pi / 2 + math.pi / (BEAMS - 1) * np.arange(BEAMS)


def wall_ranges(gamma, rho, t_range, *, beams=BEAMS, ranges=None):
    """Ranges of a scan that sees the segment of line ``(gamma, rho)`` between positions
    ``t_range`` along it (direction ``(-sin, cos)``), ``inf`` elsewhere (or over ``ranges``)."""
    angles = -math.pi / 2 + math.pi / (beams - 1) * np.arange(beams)
    out = np.full(beams, math.inf) if ranges is None else ranges.copy()
    with np.errstate(divide='ignore'):
        r = rho / np.cos(angles - gamma)
    t = r * np.sin(angles - gamma)                  # position along the line of each hit
    hit = (np.cos(angles - gamma) > 0.05) & (t >= t_range[0]) & (t <= t_range[1])
    out[hit] = np.minimum(out[hit], r[hit])
    return out


@settings(max_examples=60, deadline=None)
@given(st.floats(-1.2, 1.2), st.floats(0.5, 8.0), st.floats(-2.0, 0.0), st.floats(0.8, 3.0))
def test_a_noise_free_wall_is_recovered_exactly(gamma, rho, start, length):
    ranges = wall_ranges(gamma, rho, (start, start + length))
    _, _, x, y, _ = scan_points(ranges)
    assume(len(x) >= 10 and math.hypot(x[-1] - x[0], y[-1] - y[0]) >= 0.5)   # in view
    lines = extract_lines(ranges, range_sigma=0.01)
    assert len(lines) == 1
    line = lines[0]
    assert line.gamma == pytest.approx(gamma, abs=1e-9)
    assert line.rho == pytest.approx(rho, abs=1e-9)
    assert line.length <= length + 1e-9
    assert line.points == line.last - line.first + 1
    assert np.all(np.linalg.eigvalsh(line.covariance) > 0)


@settings(max_examples=80, deadline=None, derandomize=True)
@given(st.floats(-1.2, 1.2), st.floats(0.5, 8.0), st.floats(-2.0, 0.0), st.floats(0.8, 3.0),
       st.floats(0.002, 0.03), st.integers(0, 2 ** 32 - 1))
def test_one_noisy_fit_lies_within_its_covariance(gamma, rho, start, length, sigma, seed):
    clean = wall_ranges(gamma, rho, (start, start + length))
    _, _, x, y, _ = scan_points(clean)
    assume(len(x) >= 10 and math.hypot(x[-1] - x[0], y[-1] - y[0]) >= 0.5)   # in view
    noisy = clean + np.random.default_rng(seed).normal(0.0, sigma, BEAMS)
    lines = extract_lines(noisy, range_sigma=sigma)
    assert len(lines) == 1
    e = np.array([lines[0].gamma - gamma, lines[0].rho - rho])
    assert float(e @ np.linalg.solve(lines[0].covariance, e)) < 27.6     # chi2(2) at 1 - 1e-6


@pytest.mark.parametrize('gamma, rho, span', [(0.0, 3.0, (-1.5, 1.5)), (0.9, 2.0, (-0.5, 2.5)),
                                              (-0.6, 6.0, (-3.0, 1.0)), (1.0, 1.2, (-1.0, 0.3))])
def test_fits_of_noisy_walls_are_within_their_covariance(gamma, rho, span):
    """Monte Carlo: the normalised error (NEES) of (gamma, rho) averages 2, its dimension."""
    rng = np.random.default_rng(11)
    sigma = 0.01
    clean = wall_ranges(gamma, rho, span)
    nees = []
    for _ in range(400):
        lines = extract_lines(clean + rng.normal(0.0, sigma, BEAMS), range_sigma=sigma)
        assert len(lines) == 1
        e = np.array([lines[0].gamma - gamma, lines[0].rho - rho])
        nees.append(float(e @ np.linalg.solve(lines[0].covariance, e)))
    assert 1.7 < np.mean(nees) < 2.3
    assert np.mean(np.array(nees) > 9.21) < 0.03          # the 99 % gate holds


@pytest.mark.parametrize('scan', [np.full(BEAMS, -1.0), np.full(BEAMS, math.inf),
                                  np.full(BEAMS, math.nan), np.full(181, -1.0),
                                  np.full(BEAMS, 90.0), np.zeros(BEAMS)])
def test_scans_without_readings_give_no_lines(scan):
    assert extract_lines(scan, max_range=81.0) == []


def test_invalid_beams_and_gaps_break_lines():
    ranges = wall_ranges(0.0, 3.0, (-2.0, 2.0))
    broken = ranges.copy()
    broken[175:185] = -1.0                          # the laser's error code on ten beams
    assert len(extract_lines(ranges)) == 1
    assert len(extract_lines(broken)) == 2
    one_nan = ranges.copy()
    one_nan[180] = math.nan
    assert [(line.first, line.last) for line in extract_lines(one_nan)] == [(113, 179), (181, 247)]
    # A step in depth (a door into a deeper room) breaks the wall, even with no missing beam.
    stepped = wall_ranges(0.0, 3.0, (0.0, 2.0), ranges=wall_ranges(0.0, 3.6, (-2.4, 0.0)))
    lines = extract_lines(stepped)
    assert sorted(round(line.rho, 6) for line in lines) == [3.0, 3.6]


def test_a_corner_gives_two_lines_meeting_there():
    # Walls x = 3 (gamma 0) for y in [-2, 1] and y = 1 (gamma pi/2) for x in [0.5, 3].
    ranges = wall_ranges(0.0, 3.0, (-2.0, 1.0))
    ranges = wall_ranges(math.pi / 2, 1.0, (-3.0, -0.5), ranges=ranges)
    lines = extract_lines(ranges)
    assert len(lines) == 2
    assert sorted(round(line.gamma, 6) for line in lines) == [0.0, round(math.pi / 2, 6)]
    corner = np.array([3.0, 1.0])
    assert min(np.linalg.norm(end - corner) for line in lines for end in (line.start, line.end)) < 0.05


def test_short_and_sparse_pieces_are_dropped_and_defaults_documented():
    ranges = wall_ranges(0.0, 3.0, (0.0, 0.3))     # 0.3 m: below the 0.4 m minimum length
    assert extract_lines(ranges) == []
    assert len(extract_lines(ranges, min_length=0.2)) == 1
    assert extract_lines(ranges, min_length=0.2, min_points=100) == []


def test_explicit_angles_equal_the_default_layout_and_181_beams_work():
    ranges = wall_ranges(0.4, 2.5, (-1.0, 1.0))
    a = extract_lines(ranges)
    b = extract_lines(ranges, angles=ANGLES)
    assert len(a) == len(b) == 1
    assert (a[0].first, a[0].last) == (b[0].first, b[0].last)
    assert (a[0].gamma, a[0].rho) == pytest.approx((b[0].gamma, b[0].rho), abs=1e-12)
    coarse = wall_ranges(0.4, 2.5, (-1.0, 1.0), beams=181)
    (line,) = extract_lines(coarse)
    assert line.gamma == pytest.approx(0.4) and line.rho == pytest.approx(2.5)


def test_ranges_at_or_beyond_max_range_are_no_reading():
    ranges = wall_ranges(0.0, 3.0, (-2.0, 2.0))
    assert extract_lines(ranges, max_range=3.0) == []
    index, r, x, y, _ = scan_points(ranges, max_range=3.2)
    assert np.all(r < 3.2) and len(index) == len(x) == len(y)


@pytest.mark.parametrize('kwargs, message', [
    ({'ranges': np.ones((2, 3))}, '1-D'),
    ({'ranges': np.ones(5), 'angles': np.ones(4)}, 'angles'),
    ({'ranges': np.ones(5), 'range_sigma': 0.0}, 'range_sigma'),
    ({'ranges': np.ones(5), 'min_points': 1}, 'min_points'),
])
def test_bad_input_is_refused(kwargs, message):
    ranges = kwargs.pop('ranges')
    with pytest.raises(ValueError, match=message):
        extract_lines(ranges, **kwargs)
