"""The estimation core of Pluto's slamModule (Pluto 7.2): "a compressed Kalman Filter to create a
map while also using the map to improve the pose estimates".

:class:`SlamFilter` is line-feature EKF SLAM.  The state is the laser pose ``(x, y, theta)`` in
the map frame and one landmark per wall: its infinite line ``(gamma, rho)``
(:mod:`.line_landmark`), with the part of it seen so far kept beside the state
(:mod:`.landmark_extent`) to turn lines into wall segments.  Per scan, as PoseFilter,
:meth:`~SlamFilter.predict` composes the odometry increment onto the pose and
:meth:`~SlamFilter.update` matches the scan's lines to the landmarks near the robot
(:mod:`.slam_association`), corrects pose and landmarks with the consistent matches in one EKF
update, extends the matched landmarks' extents, starts landmarks from unmatched lines, merges
landmarks that have become the same wall (how a loop closes) and prunes short-lived tentative
ones; docs/pluto-nav.md ("The SLAM filter") states each step with its settings.

Before changing it: a map error is permanent, so the filter is wary of an odometry increment worse
than its model says: it inflates the increments' covariance (``odometry_inflation``), gives lines
that fit no landmark a second, wider gate, and starts landmarks only in scans whose pose was pinned
by :data:`MIN_MATCHES_TO_MAP` matches (or once it has been adrift for ``adrift_scans`` scans).  The
Kalman filter is Guivant & Nebot's compressed EKF, as Pluto's (:mod:`.compressed_ekf`): it computes
exactly what the full EKF computes (the tests run both), and every rule that picks landmarks looks
only at landmarks the laser could see, so compression changes no decision either.

:meth:`~SlamFilter.to_map_data` saves the walls as a :class:`wurde_idl.mapfile.MapData` with the
place ``start`` where SLAM started, so the poseModule can load it as its a-priori map next run.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from wurde_idl.mapfile import MapData, Place
from wurde_idl.segments import point_segment_distance

from .compressed_ekf import CompressedEKF
from .geometry import compose, compose_jacobians, inverse, transform_points, wrap
from .landmark_extent import AnchorCandidates, Extent, choose_anchor, resolve
from .line_landmark import along, initialise, point_at
from .lines import LineFeature
from .segments import clip_to_disc
from .slam_association import associate, side_of
from .slam_correction import correct
from .slam_merge import find_merges
from .slam_settings import SlamSettings, SlamUpdate

__all__ = ['LINE_EXTRACTION', 'MIN_MATCHES_TO_MAP', 'SlamFilter', 'SlamSettings', 'SlamUpdate']

#: Keyword arguments of :func:`.lines.extract_lines` for the lines fed to a SlamFilter: a run of
#: beams breaks at a jump of more than 0.1 m plus 3 beam spacings (the default, 0.2 m plus 5,
#: keeps a wall seen at grazing incidence in one piece).  Where a box stands a few tenths of a
#: metre in front of a wall, the default keeps the first beams on the wall behind in the box's
#: run, and those within the split distance of the box's line stretch the box's side to where
#: the two lines cross; a map keeps such an end for good, while the poseModule's matching does
#: not mind it.
LINE_EXTRACTION = {'gap_distance': 0.1, 'gap_ratio': 3.0}

#: Matches a scan needs before its unmatched lines may start landmarks (and that fallback
#: matches need to be used on their own).
MIN_MATCHES_TO_MAP = 2


@dataclasses.dataclass
class _Landmark:
    """Bookkeeping beside a landmark's state: the part of its line seen, how many scans matched
    it (``seen``; its start counts), the scan it was last matched in and the sides of its line
    the laser saw it from (:data:`.slam_association.SIDE_POSITIVE` and ``SIDE_NEGATIVE``)."""

    extent: Extent
    seen: int
    last: int
    sides: int


class SlamFilter:
    """Line-feature EKF SLAM with the compressed update (see the module's description).

    Call :meth:`set_pose` first: it fixes the map frame.
    """

    def __init__(self, *, settings: SlamSettings = SlamSettings()) -> None:
        """An empty map with the laser at the origin; call :meth:`set_pose` first.

        :param settings: the filter's tunables (:class:`.slam_settings.SlamSettings`).
        """
        self.settings = settings
        self._limit = -2.0 * math.log1p(-settings.consistency_probability)
        self.set_pose((0.0, 0.0, 0.0), np.zeros((3, 3)))

    # -- reading ----------------------------------------------------------------------------------

    @property
    def pose(self) -> NDArray:
        """The laser pose ``(x, y, theta)`` in the map frame (a copy)."""
        return self._ekf.robot_mean

    @property
    def covariance(self) -> NDArray:
        """Its 3x3 covariance (a copy)."""
        return self._ekf.robot_covariance

    @property
    def start(self) -> NDArray:
        """The laser pose :meth:`set_pose` started from."""
        return self._start.copy()

    def __len__(self) -> int:
        """Number of landmarks, tentative ones included."""
        return len(self._marks)

    def state(self) -> tuple[NDArray, NDArray]:
        """Mean and covariance of the whole state: the pose, then every landmark's line
        ``(gamma, rho)`` (tentative ones too) in the order they were started.  Brings the
        compressed filter's passive part up to date (a global update)."""
        _, mean, cov = self._ekf.state()
        return mean, cov

    def walls(self) -> NDArray:
        """``(N, 4)`` the confirmed walls as segments ``x1, y1, x2, y2`` in the map frame."""
        keys = [k for k, m in self._marks.items() if m.seen >= self.settings.confirm_matches]
        if not keys:
            return np.zeros((0, 4))
        found = self._extents(keys, self._ekf.means(keys))
        long = found.intervals[:, 1] - found.intervals[:, 0] >= self.settings.min_wall_length
        ends = point_at(found.lines[long, 0:1], found.lines[long, 1:2], found.intervals[long])
        return ends.reshape(-1, 4)

    def to_map_data(self, name: str, *, mount: ArrayLike = (0.0, 0.0, 0.0)) -> MapData:
        """The map: the confirmed walls, and the place ``start`` where SLAM started.

        :param name: the map's name.
        :param mount: the laser's pose on the robot: ``start`` is the *robot's* pose (as the
            map files' places are), the laser's start composed with the inverse mount.
        """
        robot = compose(self._start, inverse(mount))
        return MapData(name, walls=tuple(map(tuple, self.walls().tolist())),
                       places={'start': Place(*(float(v) for v in robot))})

    # -- the filter -------------------------------------------------------------------------------

    def set_pose(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """Start a new map with the laser at ``pose`` (the map frame is where this puts it).

        :param pose: the laser pose ``(x, y, theta)``, metres and radians.
        :param covariance: 3x3, symmetric positive semi-definite (zero: the map frame *is* this
            pose).
        :raises ValueError: on a non-finite pose or a covariance that is not symmetric PSD.
        """
        p, c = _checked(pose, 'pose', covariance, 'covariance')
        self._start = compose(p, (0.0, 0.0, 0.0))
        self._ekf = CompressedEKF(self._start, 0.5 * (c + c.T))
        self._marks: dict[int, _Landmark] = {}
        self._keys = itertools.count()
        self._scan = 0
        self._adrift = 0
        self._zone = self._start[:2].copy()

    def predict(self, increment: ArrayLike, increment_covariance: ArrayLike) -> None:
        """Move by the odometry ``increment`` with its covariance.

        :param increment: ``(dx, dy, dtheta)`` in the previous laser frame.
        :param increment_covariance: its 3x3 covariance, before ``odometry_inflation`` multiplies it.
        :raises ValueError: on a non-finite increment or a covariance that is not symmetric PSD.
        """
        u, q = _checked(increment, 'increment', increment_covariance, 'increment_covariance')
        pose = self._ekf.robot_mean
        j_pose, j_inc = compose_jacobians(pose, u)
        q = self.settings.odometry_inflation * q
        self._ekf.predict(compose(pose, u), j_pose, j_inc @ q @ j_inc.T)

    def update(self, lines: Sequence[LineFeature]) -> SlamUpdate:
        """Correct pose and map with the lines of one scan and grow the map (see the module's
        description).

        :param lines: the scan's lines in the laser frame, best extracted with
            :data:`LINE_EXTRACTION`.
        """
        self._scan += 1
        s = self.settings
        lines = [line for line in lines
                 if float(point_segment_distance((0.0, 0.0), line.start, line.end)) <= s.max_range]
        before = self._active_extents()
        keys = before.keys.tolist()
        sides = np.array([self._marks[k].sides for k in keys], dtype=np.int64)
        found = associate(lines, self._ekf.robot_mean, self._ekf.active_covariance, before.lines,
                          before.intervals, sides, s.association)
        fix = correct(self._ekf, lines, [(k, keys[j]) for k, j in found.matches], found.fallback,
                      limit=self._limit, min_fallback=MIN_MATCHES_TO_MAP)
        pose = self._ekf.robot_mean
        candidates = self._anchor_candidates(self._active_extents())
        for k, key in fix.used:
            mark = self._marks[key]
            mark.seen += 1
            mark.last = self._scan
            mark.sides |= int(side_of(found.offsets[keys.index(key)]))
            self._extend(key, lines[k], pose, candidates)
        # Map new walls only where the pose is pinned by the map (or the map has nothing here
        # for a while): lines unmatched because the prediction was off would be mapped askew.
        pinned = len(fix.used) >= MIN_MATCHES_TO_MAP or not keys
        self._adrift = 0 if pinned else self._adrift + 1
        added = []
        if pinned or self._adrift >= s.adrift_scans:
            for k in found.unmatched:
                new_key = self._start_landmark(lines[k], pose, candidates)
                if new_key is not None:
                    added.append(new_key)
        merged = self._merge({key for _, key in fix.used} | set(added))
        pruned = self._prune(self._ekf.active)
        committed = self._maybe_repartition()
        return SlamUpdate(len(lines), len(fix.used), fix.rejected, len(found.ambiguous),
                          len(added), merged, pruned, len(self._marks), len(self._ekf.active),
                          committed, fix.nis)

    # -- map bookkeeping --------------------------------------------------------------------------

    def _lines_of(self, keys: NDArray) -> NDArray:
        """``(K, 2)`` current lines of landmarks (NaN for forgotten ones)."""
        known = np.array([int(k) in self._ekf for k in keys], dtype=bool)
        out = np.full((len(keys), 2), np.nan)
        if known.any():
            out[known] = self._ekf.means(np.asarray(keys)[known])
        return out

    def _extents(self, keys: Sequence[int], lines: NDArray) -> AnchorCandidates:
        """Landmarks ``keys`` with their current ``lines`` and resolved extents."""
        intervals = resolve([self._marks[k].extent for k in keys], lines, self._lines_of)
        return AnchorCandidates(np.array(keys, dtype=np.int64), lines, intervals)

    def _active_extents(self) -> AnchorCandidates:
        """The active landmarks with their current lines and extents."""
        return self._extents(self._ekf.active, self._ekf.active_mean[3:].reshape(-1, 2).copy())

    def _anchor_candidates(self, active: AnchorCandidates) -> AnchorCandidates:
        """The landmarks that may anchor an end seen now: the confirmed ones (a tentative line,
        seen once or twice, may still move a lot) within ``max_range + anchor_radius`` of the
        laser (all active; the rule does not depend on the local area, so compression changes no
        choice)."""
        if len(active.keys) == 0:
            return active
        ends = point_at(active.lines[:, 0:1], active.lines[:, 1:2], active.intervals)  # (K, 2, 2)
        confirmed = np.array([self._marks[int(k)].seen >= self.settings.confirm_matches for k in active.keys],
                             dtype=bool)
        near = confirmed & (point_segment_distance(self._ekf.robot_mean[:2], ends[:, 0], ends[:, 1]) <=
                            self.settings.max_range + self.settings.anchor_radius)
        return AnchorCandidates(active.keys[near], active.lines[near], active.intervals[near])

    def _seen_interval(self, line: LineFeature, pose: NDArray, landmark: NDArray
                       ) -> tuple[float, float] | None:
        """The part of an observed segment within ``extent_range`` of the laser, as ``t`` on
        ``landmark``'s line (None if no part is in range)."""
        clipped = clip_to_disc(line.start, line.end, self.settings.extent_range)
        if clipped is None:
            return None
        t = along(landmark[0], transform_points(pose, clipped))
        return float(t.min()), float(t.max())

    def _extend(self, key: int, line: LineFeature, pose: NDArray,
                candidates: AnchorCandidates) -> None:
        """Grow landmark ``key``'s extent by what ``line`` shows where it continues it."""
        landmark = self._ekf.means([key])[0]
        seen = self._seen_interval(line, pose, landmark)
        if seen is None:
            return
        extent = self._marks[key].extent
        lo, hi = extent.interval(landmark, self._lines_of)
        gap = self.settings.extend_gap
        if seen[0] > hi + gap or seen[1] < lo - gap:
            return
        anchor: dict[str, Any] = dict(exclude=key, radius=self.settings.anchor_radius,
                      min_angle=self.settings.anchor_min_angle)
        if seen[0] < lo or (extent.lo.anchor is None and seen[0] < lo + gap):
            extent.lo = choose_anchor(landmark, min(seen[0], lo), candidates, **anchor)
        if seen[1] > hi or (extent.hi.anchor is None and seen[1] > hi - gap):
            extent.hi = choose_anchor(landmark, max(seen[1], hi), candidates, **anchor)

    def _start_landmark(self, line: LineFeature, pose: NDArray,
                        candidates: AnchorCandidates) -> int | None:
        """A new landmark from an unmatched line, if it is long enough; its key."""
        s = self.settings
        if line.points < s.new_min_points:
            return None
        landmark, g_pose, g_z = initialise(line.gamma, line.rho, pose)
        seen = self._seen_interval(line, pose, landmark)
        if seen is None or seen[1] - seen[0] < s.new_min_length:
            return None
        key = next(self._keys)
        self._ekf.add(key, landmark, g_pose, g_z @ line.covariance @ g_z.T)
        anchor: dict[str, Any] = dict(exclude=key, radius=s.anchor_radius, min_angle=s.anchor_min_angle)
        extent = Extent(choose_anchor(landmark, seen[0], candidates, **anchor),
                        choose_anchor(landmark, seen[1], candidates, **anchor))
        offset = float(landmark[1] - pose[0] * math.cos(landmark[0]) -
                       pose[1] * math.sin(landmark[0]))
        self._marks[key] = _Landmark(extent, seen=1, last=self._scan, sides=int(side_of(offset)))
        return key

    def _merge(self, touched: set[int]) -> int:
        """Merge the landmarks that became one wall; the number merged away."""
        active = self._active_extents()
        keys = active.keys.tolist()
        if len(keys) < 2 or not touched:
            return 0
        merges = find_merges(active.lines, active.intervals, self._ekf.active_covariance,
                             np.array([self._marks[k].sides for k in keys], dtype=np.int64),
                             [i for i, k in enumerate(keys) if k in touched],
                             self.settings.merge)
        done = 0
        for i, j, sign in merges:
            keep, drop = keys[i], keys[j]
            if self._marks[drop].seen > self._marks[keep].seen:
                keep, drop = drop, keep
            if keep in self._ekf and drop in self._ekf:
                self._fuse(keep, drop, sign)
                done += 1
        return done

    def _fuse(self, keep: int, drop: int, sign: float) -> None:
        """Constrain landmark ``drop`` to equal ``keep`` (``sign``: -1 if in the other form),
        then forget it and join the extents."""
        a, b = self._ekf.local_index(keep), self._ekf.local_index(drop)
        lk, ld = self._ekf.means([keep, drop])
        jac = np.array([[1.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, -sign]])
        gap = np.array([wrap(lk[0] - ld[0] - (math.pi if sign < 0 else 0.0)), lk[1] - sign * ld[1]])
        ext_keep, ext_drop = self._marks[keep].extent, self._marks[drop].extent
        ext_keep.interval(lk, self._lines_of)
        ext_drop.interval(ld, self._lines_of)
        if sign < 0:
            ext_drop = ext_drop.flipped()
        self._ekf.update([a, a + 1, b, b + 1], jac, 1e-12 * np.eye(2), -gap)
        lo = ext_keep.lo if ext_keep.lo.t <= ext_drop.lo.t else ext_drop.lo
        hi = ext_keep.hi if ext_keep.hi.t >= ext_drop.hi.t else ext_drop.hi
        mark, gone = self._marks[keep], self._marks.pop(drop)
        mark.extent = Extent(lo, hi)
        mark.seen += gone.seen
        mark.last = max(mark.last, gone.last)
        mark.sides |= gone.sides
        self._ekf.remove(drop)
        for other in self._marks.values():
            for end in (other.extent.lo, other.extent.hi):
                if end.anchor == drop:
                    end.anchor = keep                  # the same line: the same crossing
        for end in (mark.extent.lo, mark.extent.hi):
            if end.anchor in (keep, drop):
                end.unanchor(lk)

    def _prune(self, keys: Sequence[int]) -> int:
        """Drop tentative landmarks unseen for ``tentative_scans`` scans."""
        s = self.settings
        stale = [k for k in keys if self._marks[k].seen < s.confirm_matches
                 and self._scan - self._marks[k].last >= s.tentative_scans]
        for key in stale:
            self._forget(key)
        return len(stale)

    def _forget(self, key: int) -> None:
        for other_key, other in self._marks.items():
            if key in (other.extent.lo.anchor, other.extent.hi.anchor):
                line = self._ekf.means([other_key])[0]
                other.extent.interval(line, self._lines_of)
                other.extent.drop_anchor(key, line)
        del self._marks[key]
        self._ekf.remove(key)

    def _maybe_repartition(self) -> bool:
        """Global update and a new local area when the robot has left the current one."""
        pose = self._ekf.robot_mean
        s = self.settings
        if math.dist(pose[:2], self._zone) <= s.zone_radius:
            return False
        self._ekf.commit()
        active = set(self._ekf.active)
        self._prune([k for k in self._ekf.keys if k not in active])
        cov = self._ekf.robot_covariance
        # Everything a line seen from the local area can match, merge with or anchor to.
        reach = s.max_range + s.zone_radius + max(s.anchor_radius, 1.0) + \
            3.0 * math.sqrt(max(cov[0, 0] + cov[1, 1], 0.0))
        every = self._extents(self._ekf.keys, self._ekf.means(self._ekf.keys))
        ends = point_at(every.lines[:, 0:1], every.lines[:, 1:2], every.intervals)
        near = point_segment_distance(pose[:2], ends[:, 0], ends[:, 1]) <= reach
        self._ekf.activate(every.keys[near].tolist())
        self._zone = pose[:2].copy()
        return True


def _checked(vector: ArrayLike, vector_name: str, matrix: ArrayLike, matrix_name: str
             ) -> tuple[NDArray, NDArray]:
    """A finite pose-like 3-vector and a symmetric positive semi-definite 3x3 matrix (rounding
    below 1e-12 of its largest entry forgiven).

    :raises ValueError: naming the argument that is not.
    """
    v = np.asarray(vector, dtype=np.float64).reshape(3)
    m = np.asarray(matrix, dtype=np.float64).reshape(3, 3)
    if not np.isfinite(v).all():
        raise ValueError(f'{vector_name} must be finite, not {v.tolist()}')
    if not np.isfinite(m).all() or not np.allclose(m, m.T, rtol=1e-9, atol=1e-12):
        raise ValueError(f'{matrix_name} must be finite and symmetric, not {m.tolist()}')
    smallest = float(np.linalg.eigvalsh(0.5 * (m + m.T))[0])
    if smallest < -1e-12 * max(1.0, float(np.abs(m).max())):
        raise ValueError(f'{matrix_name} must be positive semi-definite; its smallest eigenvalue '
                         f'is {smallest}')
    return v, m
