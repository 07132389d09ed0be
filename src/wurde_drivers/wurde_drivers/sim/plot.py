"""A picture of a simulated run: the map, the path driven and the last laser scan, as PNG.

matplotlib's Agg backend draws without a display, so this works on a headless machine and in CI.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from .world import World  # noqa: E402

__all__ = ['plot_run']


def plot_run(world: World, path: str | os.PathLike[str], *, truth: Sequence[tuple[float, float]],
             odometry: Sequence[tuple[float, float]] = (), estimate: Sequence[tuple[float, float]] = (),
             scan_pose: tuple[float, float, float] | None = None,
             scan: Sequence[float] = (), scan_fov: float = math.pi, waypoints: Sequence[tuple[float, float]] = (),
             title: str = '') -> None:
    """Draw walls (black), off-limits (red), the true path (blue), odometry (dashed orange), a
    localization's estimate (dotted purple), waypoints (green) and the last scan's hits (red dots)
    from ``scan_pose``; save as PNG."""
    figure, axes = plt.subplots(figsize=(9, 7), dpi=100)
    for x1, y1, x2, y2 in world.walls:
        axes.plot([x1, x2], [y1, y2], color='black', linewidth=1.5)
    for polygon in world.offlimits:
        closed = list(polygon) + [polygon[0]]
        axes.fill([p[0] for p in closed], [p[1] for p in closed], color='red', alpha=0.15)
    if truth:
        axes.plot([p[0] for p in truth], [p[1] for p in truth], color='tab:blue', label='true path')
    if odometry:
        axes.plot([p[0] for p in odometry], [p[1] for p in odometry], '--', color='tab:orange',
                  label='odometry')
    if estimate:
        axes.plot([p[0] for p in estimate], [p[1] for p in estimate], ':', color='tab:purple',
                  linewidth=2, label='localization')
    if waypoints:
        axes.plot([p[0] for p in waypoints], [p[1] for p in waypoints], 'o', color='tab:green',
                  label='waypoints')
    if scan_pose is not None and len(scan):
        x, y, theta = scan_pose
        step = scan_fov / (len(scan) - 1)
        hits = [(x + r * math.cos(theta - scan_fov / 2 + i * step), y + r * math.sin(theta - scan_fov / 2 + i * step))
                for i, r in enumerate(scan) if math.isfinite(r) and r > 0]
        axes.plot([h[0] for h in hits], [h[1] for h in hits], '.', color='tab:red', markersize=3,
                  label='last laser scan')
    axes.set_aspect('equal')
    axes.set_xlabel('x (m)')
    axes.set_ylabel('y (m)')
    axes.set_title(title or world.name)
    axes.legend(loc='upper right', fontsize=8)
    figure.tight_layout()
    figure.savefig(os.fspath(path), format='png')
    plt.close(figure)
