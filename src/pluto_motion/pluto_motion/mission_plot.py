"""The mission's picture (``mission.png``): the map's walls, the true path, the estimated path with
its 2-sigma covariance ellipses at intervals, the goals by name, and the last laser scan placed at
the estimated pose (on the walls when the robot knows where it is)."""

from __future__ import annotations

import math
import pathlib

import numpy as np

from .mission_log import MissionLog

__all__ = ['plot_mission']

#: An ellipse every this many metres of the estimated path.
ELLIPSE_EVERY_M = 1.5


def _ellipse(covariance: np.ndarray) -> tuple[float, float, float]:
    """Width, height (2 sigma each side) and angle (deg) of the (x, y) block of ``covariance``."""
    block = np.asarray(covariance, dtype=float)[:2, :2]
    if not np.all(np.isfinite(block)):
        return 0.0, 0.0, 0.0
    values, vectors = np.linalg.eigh((block + block.T) / 2.0)
    values = np.clip(values, 0.0, None)
    angle = math.degrees(math.atan2(vectors[1, 1], vectors[0, 1]))
    return 4.0 * math.sqrt(values[1]), 4.0 * math.sqrt(values[0]), angle


def plot_mission(log: MissionLog, path: str | pathlib.Path, title: str = 'Pluto mission') -> None:
    """Draw ``log`` to the PNG file ``path``."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.patches import Ellipse

    figure, axes = plt.subplots(figsize=(10, 7))
    for x1, y1, x2, y2 in log.walls:
        axes.plot([x1, x2], [y1, y2], color='black', linewidth=1.5)
    truths = np.array([s.truth[:2] for s in log.samples if s.truth is not None]).reshape(-1, 2)
    estimates = np.array([s.pose[:2] for s in log.samples]).reshape(-1, 2)
    if len(truths):
        axes.plot(truths[:, 0], truths[:, 1], color='tab:green', linewidth=1.5, label='truth')
    if len(estimates):
        axes.plot(estimates[:, 0], estimates[:, 1], color='tab:blue', linewidth=1.0, linestyle='--',
                  label='Localization/Pose')
    travelled, last = 0.0, None
    for sample in log.samples:
        if last is not None:
            travelled += math.dist(last, sample.pose[:2])
        last = sample.pose[:2]
        if travelled >= ELLIPSE_EVERY_M:
            travelled = 0.0
            width, height, angle = _ellipse(sample.covariance)
            axes.add_patch(Ellipse(sample.pose[:2], width, height, angle=angle, fill=False,
                                   color='tab:blue', alpha=0.6))
    if len(log.last_scan):
        axes.scatter(log.last_scan[:, 0], log.last_scan[:, 1], s=2, color='tab:orange', label='last scan')
    for goal in log.goals:
        marker = 'o' if goal.result == 'reached' else 'x'
        axes.plot(goal.x, goal.y, marker, color='tab:red', markersize=8)
        axes.annotate(goal.name, (goal.x, goal.y), textcoords='offset points', xytext=(5, 5))
    axes.set_aspect('equal')
    axes.set_xlabel('x (m)')
    axes.set_ylabel('y (m)')
    axes.set_title(title)
    axes.legend(loc='upper right')
    figure.tight_layout()
    figure.savefig(str(path), dpi=100)
    plt.close(figure)
