"""How the localModule turns Post_Pose writes into streams (3) and (4), and who may write them.

Pluto 3: "The poseModule then calculates an improved estimate of this pose and writes it to
Localization/Post_Pose.  The localModule reads this interface and uses it to calculate an
adjustment to the dead-reckoning estimates."  The adjustment is the rigid transform ``A`` (map ←
dead-reckoning frame) that takes the dead-reckoned pose at the Post_Pose's time onto the written
pose; then Pose = A ⊕ Dead-Reckoning and Laser_Pose = A ⊕ Laser_Dead-Reckoning.  The pose written
is a laser pose when cmdFlags >= 0 and a robot pose when cmdFlags < 0 (Pluto 3).

Who may write (the setter, Pluto 7.1 and 7.2), enforced so two estimators never fight:

- a write with cmdFlags 0 releases the setter (the estimator's thread stopped); only the module
  that holds the setter may release it;
- a robot pose (cmdFlags < 0, a user setting the pose as ``pose_i`` does) is accepted only while
  no estimator holds the setter (setter <= 0);
- a laser pose with setter s > 0 is accepted when the setter is free (<= 0) or already s from the
  same module; the slamModule may switch between 2 and 3 (saving);
- anything not finite is refused.  Refusals are counted and named.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .dead_reckoning import DeadReckoning, DrSample
from .geometry import compose, compose_jacobians, inverse
from .streams import NOBODY, SLAM_SAVING, SLAM_SETTER, LocPose

__all__ = ['Adjuster', 'Refusal']

#: Covariance assumed for a written pose that carries none (a user's robot pose): 5 cm, 2 degrees.
DEFAULT_SET_COVARIANCE = np.diag([0.05 ** 2, 0.05 ** 2, np.radians(2.0) ** 2])


@dataclasses.dataclass(frozen=True)
class Refusal:
    """Why a Post_Pose write was refused."""

    source: str
    setter: int
    reason: str


class Adjuster:
    """The adjustment ``A``, the absolute covariance of the adjusted pose, and the setter."""

    def __init__(self, mount: tuple[float, float] = (0.0, 0.0)) -> None:
        self.offset = np.zeros(3)                  # A: map <- dead-reckoning frame
        self.covariance: np.ndarray | None = None  # of Pose (3); None: that of dead reckoning
        self.setter = NOBODY
        self.holder = ''
        self.mount = np.array([mount[0], mount[1], 0.0])
        self.accepted = 0
        self.refusals: list[Refusal] = []

    # -- the setter ------------------------------------------------------------------------------
    def _refuse(self, source: str, setter: int, reason: str) -> Refusal:
        refusal = Refusal(source, setter, reason)
        self.refusals.append(refusal)
        del self.refusals[:-100]
        return refusal

    def _may_write(self, setter: int, source: str) -> str | None:
        current = self.setter
        if setter == NOBODY:
            return None if current <= NOBODY or source == self.holder else \
                f'setter {current} is held by {self.holder!r}; only it may release it'
        if setter < 0:
            return None if current <= NOBODY else f'setter {current} ({self.holder!r}) is running'
        if current <= NOBODY:
            return None
        slam = {SLAM_SETTER, SLAM_SAVING}
        if source == self.holder and (setter == current or {setter, current} <= slam):
            return None
        return f'setter {current} ({self.holder!r}) is active, not {setter}'

    # -- writes ----------------------------------------------------------------------------------
    def write(self, post: LocPose, source: str, dr: DeadReckoning) -> Refusal | None:
        """Apply one Post_Pose write from module ``source``; a Refusal when it is not accepted."""
        if not post.is_finite():
            return self._refuse(source, post.setter, 'not finite')
        reason = self._may_write(post.setter, source)
        if reason is not None:
            return self._refuse(source, post.setter, reason)
        self.accepted += 1
        if post.setter == NOBODY:
            self.setter, self.holder = NOBODY, ''
            return None
        latest = dr.latest
        if latest is None:
            return self._refuse(source, post.setter, 'no odometry yet')
        then = dr.at(post.stamp) if post.stamp > 0 else None
        then = then or latest
        written = np.array(post.xytheta, dtype=float)
        covariance = post.covariance if post.covariance.shape == (3, 3) and np.all(
            np.isfinite(post.covariance)) and np.any(post.covariance) else DEFAULT_SET_COVARIANCE
        if post.setter >= 0:    # a laser pose: the robot is the laser less its mounting
            j_laser, _ = compose_jacobians(written, inverse(self.mount))
            written = compose(written, inverse(self.mount))
            covariance = j_laser @ covariance @ j_laser.T
        self.offset = compose(written, inverse(then.pose))
        since = dr.increment_between(then.stamp, latest.stamp)
        if since is not None and then is not latest:
            increment, q = since
            j_pose, j_increment = compose_jacobians(written, increment)
            covariance = j_pose @ covariance @ j_pose.T + j_increment @ q @ j_increment.T
        self.covariance = 0.5 * (covariance + covariance.T)
        self.setter, self.holder = post.setter, source
        return None

    # -- outputs ---------------------------------------------------------------------------------
    def on_step(self, sample: DrSample) -> None:
        """Grow the absolute covariance by one dead-reckoning step."""
        if self.covariance is None:
            return
        adjusted_before = compose(self.offset, compose(sample.pose, inverse(sample.increment)))
        j_pose, j_increment = compose_jacobians(adjusted_before, sample.increment)
        cov = j_pose @ self.covariance @ j_pose.T + j_increment @ sample.increment_cov @ j_increment.T
        self.covariance = 0.5 * (cov + cov.T)

    def grow(self, variance: np.ndarray) -> None:
        """Add ``variance`` (3x3) to the absolute covariance (odometry stopped: uncertainty grows)."""
        if self.covariance is not None:
            self.covariance = self.covariance + variance

    def pose(self, sample: DrSample) -> np.ndarray:
        """Pose (3): the dead-reckoned robot pose adjusted."""
        return compose(self.offset, sample.pose)

    def pose_covariance(self, sample: DrSample) -> np.ndarray:
        return sample.covariance if self.covariance is None else self.covariance

    def laser(self, robot: np.ndarray) -> np.ndarray:
        """The laser's pose for a robot pose (the laser's mounting on the robot)."""
        return compose(robot, self.mount)

