"""The SynchroMover's control law (pluto_motion.vector_follower), on an ideal differential drive."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from pluto_motion.vector_follower import MoverLimits, VectorFollower, wrap

DT = 0.05


def drive(follower: VectorFollower, pose: tuple[float, float, float], steps: int = 2000):
    """Run the law until done; the poses driven."""
    path = [pose]
    for _ in range(steps):
        out = follower.step(pose)
        if out.done:
            return path, True
        x, y, th = pose
        assert abs(out.tv) <= follower.limits.max_tv + 1e-9 and abs(out.rv) <= follower.limits.max_rv + 1e-9
        pose = (x + out.tv * math.cos(th) * DT, y + out.tv * math.sin(th) * DT, wrap(th + out.rv * DT))
        path.append(pose)
    return path, False


@settings(max_examples=60, deadline=None)
@given(st.floats(0.2, 5.0), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi))
def test_a_vector_is_driven_to_its_end(magnitude: float, angle: float, theta: float) -> None:
    follower = VectorFollower()
    follower.set_vector((1.0, 2.0, theta), magnitude, angle)
    goal = (1.0 + magnitude * math.cos(theta + angle), 2.0 + magnitude * math.sin(theta + angle))
    path, done = drive(follower, (1.0, 2.0, theta))
    assert done
    assert math.dist(path[-1][:2], goal) <= 2 * MoverLimits().reach_m
    # Never further from the goal than the start plus a turn's wobble: no overshoot and return.
    assert max(math.dist(p[:2], goal) for p in path) <= magnitude + 0.05


def test_a_zero_vector_turns_on_the_spot_and_a_new_vector_overrides() -> None:
    follower = VectorFollower()
    follower.set_vector((0.0, 0.0, 0.0), 0.0, 1.0)
    path, done = drive(follower, (0.0, 0.0, 0.0))
    assert done and abs(wrap(path[-1][2] - 1.0)) <= MoverLimits().reach_rad + 0.05
    assert all(math.hypot(p[0], p[1]) < 1e-9 for p in path)
    follower.set_vector((0.0, 0.0, 0.0), 3.0, 0.0)
    follower.set_vector((0.0, 0.0, 0.0), 1.0, 0.0)          # the new goal wins
    path, done = drive(follower, (0.0, 0.0, 0.0))
    assert done and abs(path[-1][0] - 1.0) < 0.1


def test_non_finite_vectors_are_refused() -> None:
    follower = VectorFollower()
    with pytest.raises(ValueError):
        follower.set_vector((0.0, 0.0, 0.0), math.nan, 0.0)
    with pytest.raises(ValueError):
        follower.set_goal(math.inf, 0.0)
    assert not follower.active
