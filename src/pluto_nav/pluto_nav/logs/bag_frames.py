"""Where a bag's laser sits on the robot: the transform tree of ``/tf_static`` and ``/tf``, and a
laser frame's pose on the base frame projected to the plane (x, y, yaw) with the beam order.

A TF tree holds, per child frame, its parent and the latest transform (REP-105: each frame has one
parent).  The laser's pose on the base is the chain base -> ... -> laser through their lowest
common ancestor, so a laser under ``base_link`` is found from ``base_footprint`` too.  A laser
mounted upside down (rolled by pi, its z axis down) sees its beams in the mirrored order: a beam at
angle ``a`` in its frame points at ``yaw - a`` on the robot; :func:`laser_geometry` turns that (and
clockwise scans: a negative ``angle_increment``) into the counter-clockwise order of
:class:`~.records.LaserConfig`.
"""

from __future__ import annotations

import builtins
import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from .records import LaserConfig, Pose2D

__all__ = ['FrameTree', 'PlanarMount', 'frame_name', 'laser_geometry', 'planar_mount', 'transform_matrix',
           'TILT_NOTICE']

Matrix = NDArray[np.float64]
#: A laser whose plane leans more than this from the base's plane is projected with a notice.
TILT_NOTICE = math.radians(5.0)


def frame_name(frame_id: str) -> str:
    """A frame id as TF2 compares it: ROS 1's leading ``/`` dropped.

    :param frame_id: a message's frame id.
    """
    return frame_id.lstrip('/')


def transform_matrix(translation: tuple[float, float, float],
                     rotation: tuple[float, float, float, float]) -> Matrix | None:
    """The 4x4 homogeneous transform of a translation and a quaternion, normalised.

    :param translation: (x, y, z) in metres.
    :param rotation: the quaternion (x, y, z, w), of any length but zero.
    :returns: the matrix; None for a quaternion of zero length (no rotation given) or a value that
        is not finite.
    """
    x, y, z, w = rotation
    norm = x * x + y * y + z * z + w * w
    if not norm > 1e-12 or not math.isfinite(norm) or not all(math.isfinite(v) for v in translation):
        return None
    s = 2.0 / norm
    matrix = np.eye(4)
    matrix[:3, :3] = [[1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
                      [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
                      [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)]]
    matrix[:3, 3] = translation
    return matrix


class FrameTree:
    """Each child frame's parent and latest transform (parent <- child), from TF messages."""

    def __init__(self) -> None:
        self._edges: dict[str, tuple[str, Matrix]] = {}

    def __contains__(self, frame: str) -> bool:
        return frame in self._edges or any(parent == frame for parent, _ in self._edges.values())

    def set(self, parent: str, child: str, matrix: Matrix) -> None:
        """The transform of ``child`` in ``parent`` (later ones replace earlier ones).

        :param parent: the parent frame's name (as :func:`frame_name` gives it).
        :param child: the child frame's name; a transform of a frame in itself is ignored.
        :param matrix: 4x4, parent <- child.
        """
        if parent != child:
            self._edges[child] = (parent, matrix)

    def _up(self, frame: str) -> dict[str, tuple[Matrix, list[str]]]:
        """Every ancestor of ``frame`` (itself included): ``frame``'s pose in it and the child
        frames of the edges walked."""
        found: dict[str, tuple[Matrix, list[str]]] = {frame: (np.eye(4), [])}
        pose: Matrix = np.eye(4)
        walked: list[str] = []
        while frame in self._edges:
            parent, matrix = self._edges[frame]
            if parent in found:                     # a loop in a broken tree
                break
            pose, walked = matrix @ pose, walked + [frame]
            found[parent] = (pose, walked)
            frame = parent
        return found

    def lookup(self, target: str, source: str) -> tuple[Matrix, builtins.set[str]] | None:
        """``source``'s pose in ``target`` and the child frames of the edges used.

        :param target: the frame to express the pose in.
        :param source: the frame whose pose is wanted.
        :returns: the 4x4 transform (target <- source) and the set of child frames walked; None when the
            two are not connected.
        """
        of_source = self._up(source)
        pose: Matrix = np.eye(4)
        walked: list[str] = []
        frame = target
        while True:
            if frame in of_source:
                source_pose, source_walked = of_source[frame]
                return np.linalg.inv(pose) @ source_pose, set(walked) | set(source_walked)
            if frame not in self._edges or frame in walked:
                return None
            parent, matrix = self._edges[frame]
            pose, walked = matrix @ pose, walked + [frame]
            frame = parent


@dataclasses.dataclass(frozen=True)
class PlanarMount:
    """A laser's pose on the base in the plane, and whether its beams turn the other way.

    :ivar pose: (x, y, yaw) of the laser's x axis on the base.
    :ivar mirrored: its z axis points down (mounted upside down): beam angles change sign.
    :ivar tilt: rad between the laser's scan plane and the base's plane (0 when level, upside
        down or not).
    """

    pose: Pose2D
    mirrored: bool
    tilt: float


def planar_mount(matrix: Matrix) -> PlanarMount:
    """The plane's share of a laser's 3-D pose on the base.

    :param matrix: 4x4, base <- laser.
    """
    rotation = matrix[:3, :3]
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    up = float(np.clip(rotation[2, 2], -1.0, 1.0))
    pose = (float(matrix[0, 3]), float(matrix[1, 3]), yaw)
    return PlanarMount(pose, up < 0.0, math.acos(abs(up)))


def laser_geometry(angle_min: float, angle_increment: float, count: int, range_min: float,
                   range_max: float, mount: PlanarMount) -> tuple[LaserConfig, bool]:
    """The :class:`LaserConfig` of a LaserScan's fields on ``mount``.

    :param angle_min: rad, the LaserScan's first beam's angle.
    :param angle_increment: rad between beams (negative: the beams turn clockwise).
    :param count: the number of beams.
    :param range_min: m, the LaserScan's ``range_min``.
    :param range_max: m, the LaserScan's ``range_max``.
    :param mount: the laser's pose on the base (:func:`planar_mount`).
    :returns: the config and whether the ranges must be reversed to be in its (counter-clockwise)
        beam order.
    """
    sign = -1.0 if mount.mirrored else 1.0
    start, step = sign * angle_min, sign * angle_increment
    reverse = step < 0.0
    if reverse:
        start, step = start + (count - 1) * step, -step
    return LaserConfig(start, step, range_max, range_min, mount.pose), reverse
