"""The estimators' scan-by-scan cycle without ROS: what the poseModule and slamModule run on the
localModule's streams, and ``offline_nav`` runs on a recording — one code, two ways in.

A :class:`Method` is the estimation itself (Pluto's line features and Kalman filters, or scan
matching): it starts at a pose, predicts with the laser's odometry increment and updates with a
scan.  :class:`ScanCycle` is Pluto's cycle round it (:mod:`.estimator` says it for the modules):
the first scan sets the start, every later one predicts with the increment of the laser's dead
reckoning since the scan before and then updates.  A :class:`Scan` is one laser scan with its
line features computed on first use (the line methods need them, scan matching does not).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .geometry import relative
from .lines import LineFeature, extract_lines, scan_points
from .point_map import voxel_filter

__all__ = ['DEFAULT_INCREMENT_COV', 'Method', 'Scan', 'ScanCycle']

#: Covariance used for an increment that comes without one.
DEFAULT_INCREMENT_COV = np.diag([1e-4, 1e-4, 1e-4])


@dataclasses.dataclass
class Scan:
    """One laser scan: ``ranges`` (m; inf: nothing within range; -1 everywhere: the laser's fatal
    error, Pluto 8.1) at ``angles`` (rad, the laser's frame), taken at ``stamp``."""

    stamp: float
    ranges: NDArray
    angles: NDArray
    max_range: float = np.inf
    _lines: dict[tuple[tuple[str, float], ...], list[LineFeature]] = dataclasses.field(
        default_factory=dict, repr=False)

    @property
    def fatal(self) -> bool:
        return bool(np.all(self.ranges == -1.0))

    def lines(self, **options: Any) -> list[LineFeature]:
        """The scan's straight walls (:func:`.lines.extract_lines` with ``options``), computed once."""
        key = tuple(sorted(options.items()))
        if key not in self._lines:
            self._lines[key] = extract_lines(self.ranges, angles=self.angles, max_range=self.max_range,
                                             **options)
        return self._lines[key]

    def points(self, voxel: float, *, min_range: float = 0.0, max_range: float = np.inf) -> NDArray:
        """The scan's echoes as ``(N, 2)`` points in the laser's frame, thinned to one per
        ``voxel`` m cell (what scan matching and the re-localization's fit work on).

        :param voxel: m, the cell size of :func:`.point_map.voxel_filter`.
        :param min_range: m; a range at or below it is no echo.
        :param max_range: m; a range at or beyond it (or the scan's own) is no echo.
        """
        _, _, x, y, _ = scan_points(self.ranges, angles=self.angles, min_range=min_range,
                                    max_range=min(max_range, self.max_range))
        return voxel_filter(np.column_stack([x, y]), voxel)


class Method(Protocol):
    """An estimation method: a filter or a SLAM over the laser's pose."""

    @property
    def pose(self) -> Any: ...
    @property
    def covariance(self) -> Any: ...
    def set_pose(self, pose: Any, covariance: Any) -> None: ...
    def predict(self, increment: Any, increment_covariance: Any) -> None: ...
    def update(self, scan: Scan) -> bool: ...


class ScanCycle:
    """Pluto's estimate cycle round a :class:`Method` (see the module's description)."""

    def __init__(self, method: Method) -> None:
        self.method = method
        self.previous: NDArray | None = None

    @property
    def started(self) -> bool:
        return self.previous is not None

    def restart(self) -> None:
        """The next scan starts the method again (from the start pose given with it)."""
        self.previous = None

    def predict(self, laser_dr: ArrayLike, covariance: ArrayLike | None) -> None:
        """The laser's dead-reckoned pose at a new scan: predict with the increment since the last."""
        now = np.asarray(laser_dr, dtype=np.float64).reshape(3)
        if self.previous is not None:
            cov = covariance if covariance is not None and np.all(np.isfinite(covariance)) else DEFAULT_INCREMENT_COV
            self.method.predict(relative(self.previous, now), cov)
        self.previous = now

    def step(self, scan: Scan, laser_dr: ArrayLike, covariance: ArrayLike | None, *,
             start: tuple[ArrayLike, ArrayLike] | None = None) -> bool | None:
        """One scan.  The first scan starts the method at ``start`` (pose, covariance) and is used
        as its first update; without ``start`` it is skipped (None).  A scan of the laser's fatal
        error only predicts (None).  Otherwise: whether the update matched something."""
        if scan.fatal:                   # Pluto 8.1: no laser data; dead reckoning only
            if self.previous is not None:
                self.predict(laser_dr, covariance)
            return None
        if self.previous is None:
            if start is None:
                return None
            self.method.set_pose(np.asarray(start[0], dtype=np.float64), np.asarray(start[1], dtype=np.float64))
            self.previous = np.asarray(laser_dr, dtype=np.float64).reshape(3)
        else:
            self.predict(laser_dr, covariance)
        return bool(self.method.update(scan))
