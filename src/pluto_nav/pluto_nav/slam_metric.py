"""How good a trajectory is: the relation metric of Kümmerle et al., and relative pose error.

Kümmerle, Steder, Dornhege, Ruhnke, Grisetti, Stachniss and Kleiner, "On measuring the accuracy of
SLAM algorithms", Autonomous Robots 27(4), 2009: a relation file lists pairs of scan times with
the robot's true displacement between them (``t1 t2 dx dy dz roll pitch dyaw``, the displacement
in the frame of the pose at ``t1``).  For each relation the estimated displacement is compared
with the true one; the score is the mean and standard deviation of the absolute translational
error (m) and of the absolute rotational error (deg).  Relations whose times are not both in the
trajectory (within :data:`TIME_TOLERANCE`) are not scored and are counted.

:func:`relative_pose_error` compares a trajectory with a reference trajectory on the pairs of
their common times whose reference poses lie ``min_distance`` to ``max_distance`` apart.

Trajectories are TUM files (``timestamp x y z qx qy qz qw``, what ``evo`` reads; the heading is
the quaternion's yaw), or a FLIRT-style graph log as a reference (``VERTEX2 id x y theta`` lines,
each followed by the ``ROBOTLASER1`` line of its scan, whose IPC timestamp is its time).
"""

from __future__ import annotations

import dataclasses
import gzip
import math
import os
from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from .geometry import relative, wrap

__all__ = ['Score', 'TIME_TOLERANCE', 'load_relations', 'load_trajectory', 'relation_error',
           'relative_pose_error', 'save_tum']

#: s: a relation's time and a trajectory's time are the same scan when this close.
TIME_TOLERANCE = 1e-3


@dataclasses.dataclass(frozen=True)
class Score:
    """:ivar count: pairs scored; ``missing`` pairs not scored (a time not in the trajectory)."""

    count: int
    missing: int
    translation: float
    translation_std: float
    rotation_deg: float
    rotation_deg_std: float

    def line(self) -> str:
        return (f'{self.count} pairs: translation {self.translation:.4f} m (std {self.translation_std:.4f}), '
                f'rotation {self.rotation_deg:.3f} deg (std {self.rotation_deg_std:.3f})'
                + (f'; {self.missing} not in the trajectory' if self.missing else ''))


class MetricError(ValueError):
    """A relation or trajectory file that cannot be read: names the file and the line."""


def _open_text(path: str | os.PathLike[str]) -> Iterable[str]:
    path = os.fspath(path)
    with open(path, 'rb') as probe:
        gz = probe.read(2) == b'\x1f\x8b'
    opener = gzip.open if gz else open
    with opener(path, 'rt', encoding='utf-8', errors='replace') as stream:
        yield from stream


def _rows(path: str | os.PathLike[str], count: int) -> tuple[NDArray, list[int]]:
    rows, lines = [], []
    try:
        for number, line in enumerate(_open_text(path), start=1):
            words = line.split()
            if not words or words[0].startswith('#'):
                continue
            try:
                values = [float(w) for w in words[:count]]
            except ValueError as error:
                raise MetricError(f'{path}:{number}: not a number: {error}') from error
            if len(values) < count or not all(math.isfinite(v) for v in values):
                raise MetricError(f'{path}:{number}: need {count} finite numbers, got {line.strip()!r}')
            rows.append(values)
            lines.append(number)
    except OSError as error:
        raise MetricError(f'{path}: cannot be read: {error.strerror or error}') from error
    return np.array(rows, dtype=np.float64).reshape(-1, count), lines


def load_relations(path: str | os.PathLike[str]) -> NDArray:
    """The relations of a relation file (Kümmerle et al.'s format, plain or gzip).

    :param path: the file: ``t1 t2 dx dy dz roll pitch dyaw`` a line, ``#`` comments.
    :returns: ``(N, 5)``: ``t1, t2, dx, dy`` and ``dyaw`` of each relation.
    :raises MetricError: the file cannot be read, or a line is not 8 finite numbers.
    """
    rows, _ = _rows(path, 8)
    return rows[:, [0, 1, 2, 3, 7]]


def load_trajectory(path: str | os.PathLike[str]) -> tuple[NDArray, NDArray]:
    """``(stamps, poses)`` of a TUM file or a graph log (see the module's description).

    :param path: the trajectory file, plain or gzip; a graph log is told by its ``VERTEX2`` or
        ``VERTEX_SE2`` lines.
    :returns: ``(N,)`` seconds and ``(N, 3)`` poses ``(x, y, theta)``.
    :raises MetricError: a malformed file.
    :raises OSError: a file that cannot be opened.
    """
    head = next(iter(_open_text(path)), '')
    if head.split()[:1] in (['VERTEX2'], ['VERTEX_SE2']) or _looks_like_graph(path):
        return _load_graph_log(path)
    rows, _ = _rows(path, 8)
    qx, qy, qz, qw = rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7]
    yaw = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    return rows[:, 0], np.column_stack([rows[:, 1], rows[:, 2], yaw])


def _looks_like_graph(path: str | os.PathLike[str]) -> bool:
    for number, line in enumerate(_open_text(path)):
        if line.startswith(('VERTEX2', 'VERTEX_SE2')):
            return True
        if number > 20:
            return False
    return False


def _load_graph_log(path: str | os.PathLike[str]) -> tuple[NDArray, NDArray]:
    vertices: dict[int, NDArray] = {}
    stamps: dict[int, float] = {}
    current = None
    for number, line in enumerate(_open_text(path), start=1):
        words = line.split()
        try:
            if words[:1] in (['VERTEX2'], ['VERTEX_SE2']):
                current = int(words[1])
                vertices[current] = np.array(words[2:5], dtype=np.float64)
            elif words[:1] == ['ROBOTLASER1'] and current is not None:
                stamps[current] = float(words[-3])
                current = None
        except (ValueError, IndexError) as error:
            raise MetricError(f'{path}:{number}: a malformed {words[0]} line') from error
    ids = sorted(set(vertices) & set(stamps))
    if not ids:
        raise MetricError(f'{path}: no VERTEX2 with a ROBOTLASER1 line after it')
    order = np.argsort([stamps[i] for i in ids])
    return (np.array([stamps[ids[k]] for k in order]), np.array([vertices[ids[k]] for k in order]))


def save_tum(path: str | os.PathLike[str], stamps: ArrayLike, poses: ArrayLike) -> None:
    """Write a TUM trajectory: one line per pose, ``timestamp x y 0 0 0 sin(theta/2) cos(theta/2)``.

    :param path: the file to write (replaced).
    :param stamps: ``(N,)`` seconds.
    :param poses: ``(N, 3)`` ``(x, y, theta)``, metres and radians.
    """
    with open(path, 'w', encoding='ascii') as out:
        out.write('# timestamp x y z qx qy qz qw\n')
        for t, (x, y, theta) in zip(np.asarray(stamps, dtype=float), np.asarray(poses, dtype=float).reshape(-1, 3)):
            out.write(f'{t:.6f} {x:.6f} {y:.6f} 0 0 0 {math.sin(theta / 2):.9f} {math.cos(theta / 2):.9f}\n')


def _match(stamps: NDArray, times: NDArray) -> NDArray:
    """For each of ``times``, the index of the same time in sorted ``stamps``, or -1."""
    index = np.clip(np.searchsorted(stamps, times), 1, max(1, len(stamps) - 1))
    if len(stamps) == 0:
        return np.full(len(times), -1)
    before = np.clip(index - 1, 0, len(stamps) - 1)
    after = np.clip(index, 0, len(stamps) - 1)
    pick = np.where(np.abs(stamps[before] - times) <= np.abs(stamps[after] - times), before, after)
    return np.where(np.abs(stamps[pick] - times) <= TIME_TOLERANCE, pick, -1)


def _summary(errors: list[tuple[float, float]], missing: int) -> Score:
    if not errors:
        return Score(0, missing, math.nan, math.nan, math.nan, math.nan)
    e = np.array(errors)
    rot = np.degrees(e[:, 1])
    return Score(len(e), missing, float(e[:, 0].mean()), float(e[:, 0].std()), float(rot.mean()), float(rot.std()))


def relation_error(stamps: ArrayLike, poses: ArrayLike, relations: NDArray) -> Score:
    """The relation metric (see the module's description).

    :param stamps: ``(N,)`` seconds of the trajectory's poses, in any order.
    :param poses: ``(N, 3)`` the trajectory's ``(x, y, theta)``.
    :param relations: ``(M, 5)`` as :func:`load_relations` gives them.
    """
    t = np.asarray(stamps, dtype=np.float64)
    order = np.argsort(t, kind='stable')
    t, p = t[order], np.asarray(poses, dtype=np.float64).reshape(-1, 3)[order]
    first, second = _match(t, relations[:, 0]), _match(t, relations[:, 1])
    errors = []
    for i, j, rel in zip(first, second, relations):
        if i < 0 or j < 0:
            continue
        d = relative(p[i], p[j])
        errors.append((math.hypot(d[0] - rel[2], d[1] - rel[3]), abs(float(wrap(d[2] - rel[4])))))
    return _summary(errors, int(np.sum((first < 0) | (second < 0))))


def relative_pose_error(stamps: ArrayLike, poses: ArrayLike, ref_stamps: ArrayLike, ref_poses: ArrayLike, *,
                        min_distance: float = 0.3, max_distance: float = 2.0) -> Score:
    """Relative pose error against a reference trajectory.

    :param stamps: ``(N,)`` seconds of the trajectory's poses, in any order.
    :param poses: ``(N, 3)`` the trajectory's ``(x, y, theta)``.
    :param ref_stamps: ``(M,)`` seconds of the reference's poses.
    :param ref_poses: ``(M, 3)`` the reference's ``(x, y, theta)``.
    :param min_distance: m; pairs of common times whose reference poses are closer are not scored.
    :param max_distance: m; nor are pairs farther apart.
    """
    t = np.asarray(stamps, dtype=np.float64)
    order = np.argsort(t, kind='stable')
    t, p = t[order], np.asarray(poses, dtype=np.float64).reshape(-1, 3)[order]
    rt, rp = np.asarray(ref_stamps, dtype=np.float64), np.asarray(ref_poses, dtype=np.float64).reshape(-1, 3)
    index = _match(t, rt)
    known = index >= 0
    est, ref = p[index[known]], rp[known]
    pairs = np.array(sorted(cKDTree(ref[:, :2]).query_pairs(max_distance)), dtype=np.intp).reshape(-1, 2)
    a, b = pairs[:, 0], pairs[:, 1]
    keep = np.hypot(*(ref[a, :2] - ref[b, :2]).T) >= min_distance
    d_est, d_ref = _relative(est[a[keep]], est[b[keep]]), _relative(ref[a[keep]], ref[b[keep]])
    errors = list(zip(np.hypot(*(d_est[:, :2] - d_ref[:, :2]).T), np.abs(wrap(d_est[:, 2] - d_ref[:, 2]))))
    return _summary(errors, int((~known).sum()))


def _relative(a: NDArray, b: NDArray) -> NDArray:
    """Row-wise :func:`.geometry.relative`."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    return np.column_stack([c * dx + s * dy, -s * dx + c * dy, wrap(b[:, 2] - a[:, 2])])
