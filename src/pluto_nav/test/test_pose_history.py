"""PoseHistory: the odometry's pose at a scan's stamp."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pluto_nav.pose_history import PoseHistory


def test_between_samples_the_pose_is_interpolated() -> None:
    history = PoseHistory()
    history.add(10.0, (0.0, 0.0, 0.0))
    history.add(10.1, (0.04, 0.0, 0.1))
    assert history.at(10.05) == pytest.approx((0.02, 0.0, 0.05))
    assert history.at(10.0) == (0.0, 0.0, 0.0)
    assert history.at(10.1) == pytest.approx((0.04, 0.0, 0.1))


def test_a_turn_across_pi_goes_the_short_way() -> None:
    history = PoseHistory()
    history.add(1.0, (0.0, 0.0, 3.1))
    history.add(1.1, (0.0, 0.0, -3.1))
    assert abs(math.remainder(history.at(1.05)[2] - math.pi, math.tau)) < 1e-9


def test_outside_the_history_is_unknown_but_a_little_after_the_latest_is_the_latest() -> None:
    history = PoseHistory(keep_s=2.0, ahead_s=0.2)
    for i in range(50):                      # 5 s at 10 Hz: the first 3 s are forgotten
        history.add(100.0 + 0.1 * i, (0.1 * i, 0.0, 0.0))
    assert history.at(102.0) is None
    assert history.at(102.95) == pytest.approx((2.95, 0.0, 0.0))
    assert history.at(105.0) == pytest.approx((4.9, 0.0, 0.0))    # 0.1 s after the latest
    assert history.at(105.2) is None
    assert history.latest == pytest.approx(104.9)


def test_a_stamp_beyond_what_is_kept_is_another_clock() -> None:
    history = PoseHistory(keep_s=2.0)
    assert not history.beyond(1000.0)                  # nothing to compare with
    for i in range(3):
        history.add(100.0 + 0.1 * i, (0.1 * i, 0.0, 0.0))
    assert history.at(99.9) is None and not history.beyond(99.9)     # a reading just before the first
    assert not history.beyond(102.1) and history.beyond(102.3)
    assert history.beyond(1000.0) and history.beyond(0.0)


def test_an_earlier_stamp_starts_again_and_the_same_stamp_replaces() -> None:
    history = PoseHistory()
    history.add(5.0, (1.0, 0.0, 0.0))
    history.add(5.0, (2.0, 0.0, 0.0))
    assert len(history) == 1 and history.at(5.0) == (2.0, 0.0, 0.0)
    history.add(1.0, (3.0, 0.0, 0.0))        # another clock (a restarted simulation)
    assert len(history) == 1 and history.at(5.0) is None and history.at(1.0) == (3.0, 0.0, 0.0)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 0.5), st.floats(-1, 1), st.floats(-1, 1), st.floats(-3.1, 3.1)),
                min_size=2, max_size=30), st.floats(0, 1))
def test_every_stamp_within_the_history_lies_between_its_neighbours(steps, f) -> None:
    history, stamps, poses, t = PoseHistory(keep_s=1e9), [], [], 0.0
    for dt, x, y, theta in steps:
        t += dt
        history.add(t, (x, y, theta))
        stamps.append(t)
        poses.append((x, y, theta))
    i = len(stamps) // 2
    stamp = stamps[i - 1] + f * (stamps[i] - stamps[i - 1])
    x, y, _ = history.at(stamp)
    (x0, y0, _), (x1, y1, _) = poses[i - 1], poses[i]
    assert min(x0, x1) - 1e-9 <= x <= max(x0, x1) + 1e-9
    assert min(y0, y1) - 1e-9 <= y <= max(y0, y1) + 1e-9


def test_a_gap_longer_than_max_gap_is_not_covered() -> None:
    """Samples lost (a restarted base's truth not yet matched): a stamp inside the gap is unknown,
    not a straight line across it; the samples themselves and the ones beside a short gap are."""
    history = PoseHistory(keep_s=10.0, max_gap_s=0.5)
    history.add(1.0, (0.0, 0.0, 0.0))
    history.add(1.4, (0.1, 0.0, 0.0))
    history.add(4.0, (0.9, 0.0, 0.5))        # 2.6 s later
    assert history.at(1.2) == pytest.approx((0.05, 0.0, 0.0))
    assert history.at(2.5) is None and history.at(3.99) is None
    assert history.at(1.4) == pytest.approx((0.1, 0.0, 0.0)) and history.at(4.0) == (0.9, 0.0, 0.5)
    assert PoseHistory(keep_s=10.0).at(1.0) is None     # the default bridges any gap: unchanged
    unbounded = PoseHistory(keep_s=10.0)
    unbounded.add(1.0, (0.0, 0.0, 0.0))
    unbounded.add(4.0, (0.9, 0.0, 0.0))
    assert unbounded.at(2.5) == pytest.approx((0.45, 0.0, 0.0))
