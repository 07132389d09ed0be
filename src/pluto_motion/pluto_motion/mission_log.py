"""What a mission saw, and its figures: the estimated pose and the simulator's truth over time, the
goals and how they ended; distance, pose RMSE, contacts with walls.  No ROS: the mission program
(:mod:`pluto_motion.mission`) fills it, the plot (:mod:`pluto_motion.mission_plot`) draws it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

__all__ = ['Goal', 'MissionLog', 'Sample', 'Summary', 'wall_clearance']


@dataclasses.dataclass(frozen=True)
class Sample:
    """One moment: the Localization/Pose (x, y, theta, its 3x3 covariance), the truth now (or
    None), and the truth at the pose's stamp (None when not known): the pose error is measured on
    the latter, so that a pose that stopped coming (its localModule stopped) is not compared with
    where the robot has gone since."""

    t: float
    pose: tuple[float, float, float]
    covariance: np.ndarray
    truth: tuple[float, float, float] | None
    pose_truth: tuple[float, float, float] | None


@dataclasses.dataclass
class Goal:
    """A named place visited: where, when started, how it ended ('' while running)."""

    name: str
    x: float
    y: float
    started: float
    ended: float | None = None
    result: str = ''


@dataclasses.dataclass(frozen=True)
class Summary:
    """The mission's figures (truth-based ones are nan without a truth)."""

    goals: int
    reached: int
    seconds: float
    distance: float
    pose_rmse: float
    pose_max: float
    contacts: int
    clearance: float


def wall_clearance(walls: np.ndarray, x: float, y: float) -> float:
    """The distance (m) from (x, y) to the nearest wall segment of ``walls`` (rows x1, y1, x2, y2)."""
    if len(walls) == 0:
        return math.inf
    a, b = walls[:, :2], walls[:, 2:]
    d = b - a
    length2 = np.maximum((d * d).sum(axis=1), 1e-12)
    t = np.clip(((np.array([x, y]) - a) * d).sum(axis=1) / length2, 0.0, 1.0)
    nearest = a + t[:, None] * d
    return float(np.hypot(*(nearest - np.array([x, y])).T).min())


class MissionLog:
    """Samples and goals of one mission; ``walls`` and ``radius`` judge contacts."""

    def __init__(self, walls: Sequence[Sequence[float]], radius: float) -> None:
        self.walls = np.asarray(walls, dtype=float).reshape(-1, 4)
        self.radius = radius
        self.samples: list[Sample] = []
        self.goals: list[Goal] = []
        #: The last laser scan as world points (N, 2), placed at the Localization/Pose of its time.
        self.last_scan = np.zeros((0, 2))
        self._touching = False
        self.contacts = 0
        self.clearance = math.inf

    def add(self, sample: Sample) -> None:
        """Record a sample; a truth nearer a wall than the radius starts a contact (counted once
        until it is clear again)."""
        self.samples.append(sample)
        if sample.truth is not None:
            gap = wall_clearance(self.walls, sample.truth[0], sample.truth[1])
            self.clearance = min(self.clearance, gap)
            touching = gap < self.radius
            if touching and not self._touching:
                self.contacts += 1
            self._touching = touching

    def summary(self) -> Summary:
        truths = [s.truth for s in self.samples if s.truth is not None]
        paired = [(s.pose, s.pose_truth) for s in self.samples if s.pose_truth is not None]
        path = truths if truths else [s.pose for s in self.samples]
        distance = sum(math.dist(p[:2], q[:2]) for p, q in zip(path, path[1:]))
        errors = [math.dist(p[:2], t[:2]) for p, t in paired]
        rmse = math.sqrt(sum(e * e for e in errors) / len(errors)) if errors else math.nan
        seconds = self.samples[-1].t - self.samples[0].t if len(self.samples) > 1 else 0.0
        return Summary(goals=len(self.goals), reached=sum(g.result == 'reached' for g in self.goals),
                       seconds=seconds, distance=distance, pose_rmse=rmse,
                       pose_max=max(errors) if errors else math.nan,
                       contacts=self.contacts if truths else -1,
                       clearance=self.clearance)
