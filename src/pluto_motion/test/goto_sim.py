"""A small kinematic simulation for the avoid goto's pure core: a round robot in a world of wall
segments, a 361-beam laser raycast from its front, and the drive's regulator (heading gain, rate
and speed limits) between the goto's command and the motion.  No ROS; deterministic."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from pluto_motion.goto_field import FieldSettings, GotoProgress, goto_step
from pluto_motion.scan_points import Beams

LASER = Beams.fan(361, first=-math.pi / 2, step=math.pi / 360, x=0.2)
Segment = tuple[float, float, float, float]


def box(x0: float, y0: float, x1: float, y1: float) -> list[Segment]:
    return [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]


def raycast(walls: Sequence[Segment], x: float, y: float, angles: np.ndarray, max_range: float = 8.0) -> np.ndarray:
    """Range along each world angle from (x, y) to the nearest wall (inf beyond ``max_range``)."""
    w = np.asarray(walls, dtype=float)
    dx, dy = np.cos(angles)[:, None], np.sin(angles)[:, None]
    ex, ey = (w[:, 2] - w[:, 0])[None, :], (w[:, 3] - w[:, 1])[None, :]
    qx, qy = (w[:, 0] - x)[None, :], (w[:, 1] - y)[None, :]
    den = dx * ey - dy * ex
    with np.errstate(divide='ignore', invalid='ignore'):
        t = (qx * ey - qy * ex) / den
        u = (qx * dy - qy * dx) / den
    t = np.where((np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1), t, np.inf)
    r = t.min(axis=1)
    return np.where(r <= max_range, r, np.inf)


def clearance(walls: Sequence[Segment], x: float, y: float) -> float:
    """Distance from (x, y) to the nearest wall."""
    best = math.inf
    for x0, y0, x1, y1 in walls:
        ex, ey = x1 - x0, y1 - y0
        f = max(0.0, min(1.0, ((x - x0) * ex + (y - y0) * ey) / (ex * ex + ey * ey)))
        best = min(best, math.hypot(x - x0 - f * ex, y - y0 - f * ey))
    return best


@dataclasses.dataclass
class Run:
    result: str            # 'reached', 'stuck', 'timeout'
    path: list[tuple[float, float, float]]
    min_clearance: float
    seconds: float


def run_goto(walls: Sequence[Segment], start: tuple[float, float, float], goal: tuple[float, float], *,
             max_tv: float = 0.5, max_rv: float = 1.0, strength: float = 1.0, dt: float = 0.1,
             limit_s: float = 120.0, settings: FieldSettings = FieldSettings(),
             scan_age: tuple[float, float] | None = None, period: tuple[float, float] | None = None,
             seed: int = 0) -> Run:
    """The goto from ``start`` to ``goal``.  A loaded computer: ``scan_age`` (s, low and high)
    draws how old the scan each step uses is (its points moved into the robot's frame now, as the
    avoidModule places them), ``period`` how long each step lasts (else ``dt``); from ``seed``."""
    rng = np.random.default_rng(seed)
    scans: list[tuple[float, tuple[float, float, float], np.ndarray]] = []
    x, y, theta = start
    tv = 0.0
    side = 0
    progress = GotoProgress(settings)
    progress.start(0.0)
    path = [start]
    low = clearance(walls, x, y)
    t = 0.0
    while t < limit_s:
        c, s = math.cos(theta), math.sin(theta)
        lx, ly = x + 0.2 * c, y + 0.2 * s
        ranges = raycast(walls, lx, ly, theta + LASER.theta)
        points = LASER.points(ranges)
        if scan_age is not None:
            scans.append((t, (x, y, theta), points))
            age = rng.uniform(*scan_age)
            taken, (px, py, pt), then = next((sc for sc in reversed(scans) if sc[0] <= t - age), scans[0])
            wx = px + math.cos(pt) * then[:, 0] - math.sin(pt) * then[:, 1]
            wy = py + math.sin(pt) * then[:, 0] + math.cos(pt) * then[:, 1]
            points = np.column_stack([c * (wx - x) + s * (wy - y), -s * (wx - x) + c * (wy - y)])
        step = goto_step((x, y, theta), goal, points, max_tv=max_tv, max_rv=max_rv, strength=strength,
                         side=side, settings=settings)
        side = step.side
        if step.reached:
            return Run('reached', path, low, t)
        if progress.stuck(step, t) is not None:
            return Run('stuck', path, low, t)
        if period is not None:
            dt = rng.uniform(*period)
        error = math.atan2(math.sin(step.heading - theta), math.cos(step.heading - theta))
        rv = max(-1.5, min(1.5, settings.heading_gain * error))
        wanted = step.speed * max(0.0, math.cos(error))
        tv += max(-0.5 * dt, min(0.5 * dt, wanted - tv))
        x, y, theta = x + tv * dt * math.cos(theta), y + tv * dt * math.sin(theta), theta + rv * dt
        t += dt
        path.append((x, y, theta))
        low = min(low, clearance(walls, x, y))
    return Run('timeout', path, low, t)
