"""The robot's transform tree as ``/tf_static`` and ``/tf`` tell it, and where the laser sits.

tf2 has no Python package on PyPI here, so ``ros_inputs`` keeps the tree itself: every
``TransformStamped`` it receives is one edge parent → child (the newest wins, a child has one
parent, as in tf2); :meth:`FrameTree.lookup` composes the edges from two frames up to their first
common ancestor.  Stamps are not interpolated: the laser's mount is a fixed or slowly moving
joint, and the newest transform of each edge is what the mount is taken from.

:func:`mount_of` turns the base → laser transform into what the suite's laser info says: where
the laser sits (x, y, z in the base frame), where its x axis points (yaw) and whether it is
upside down (its z axis points down, so its counter-clockwise beams go clockwise for the robot).
Pure numpy and scipy: no rclpy.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from scipy.spatial.transform import Rotation

__all__ = ['FrameTree', 'Mount', 'Transform', 'mount_of']

#: Longest chain of frames followed (a cycle in a broken tree ends there).
MAX_DEPTH = 64


@dataclasses.dataclass(frozen=True)
class Transform:
    """A child frame in its parent: ``p_parent = rotation.apply(p_child) + translation``."""

    rotation: Rotation
    translation: np.ndarray

    @classmethod
    def identity(cls) -> Transform:
        return cls(Rotation.identity(), np.zeros(3))

    @classmethod
    def from_values(cls, translation: Sequence[float], quaternion: Sequence[float]) -> Transform:
        """From ``(x, y, z)`` and ``(qx, qy, qz, qw)`` (geometry_msgs' order).

        :raises ValueError: a value that is not finite, or a quaternion of length zero.
        """
        values = [float(v) for v in (*translation, *quaternion)]
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f'not finite: {values}')
        if math.fsum(q * q for q in values[3:]) < 1e-12:
            raise ValueError('a quaternion of length zero')
        return cls(Rotation.from_quat(values[3:]), np.array(values[:3]))

    def then(self, inner: Transform) -> Transform:
        """``self`` (a → b) followed by ``inner`` (b → c): a → c."""
        return Transform(self.rotation * inner.rotation,
                         self.translation + self.rotation.apply(inner.translation))

    def inverse(self) -> Transform:
        inverse = self.rotation.inv()
        return Transform(inverse, -inverse.apply(self.translation))


class FrameTree:
    """The newest transform of every parent → child edge heard."""

    def __init__(self) -> None:
        self._edges: dict[str, tuple[str, Transform]] = {}

    def set(self, parent: str, child: str, transform: Transform) -> None:
        """Edge ``parent`` → ``child`` (replaces the child's edge, as tf2 does)."""
        self._edges[child.lstrip('/')] = (parent.lstrip('/'), transform)

    def frames(self) -> list[str]:
        """Every frame named by an edge, sorted (for messages)."""
        return sorted(set(self._edges) | {parent for parent, _ in self._edges.values()})

    def _up(self, frame: str) -> dict[str, Transform]:
        """Each ancestor of ``frame`` (and itself) → the transform of ``frame`` in it."""
        chain = {frame: Transform.identity()}
        current, transform = frame, Transform.identity()
        for _ in range(MAX_DEPTH):
            edge = self._edges.get(current)
            if edge is None or edge[0] in chain:
                break
            current, transform = edge[0], edge[1].then(transform)
            chain[current] = transform
        return chain

    def lookup(self, target: str, source: str) -> Transform | None:
        """``source`` in ``target`` (``p_target = T p_source``), or None when no chain of edges
        joins them."""
        target, source = target.lstrip('/'), source.lstrip('/')
        from_source = self._up(source)
        if target in from_source:
            return from_source[target]
        current, to_target = target, Transform.identity()
        for _ in range(MAX_DEPTH):
            if current in from_source:
                return to_target.inverse().then(from_source[current])
            edge = self._edges.get(current)
            if edge is None:
                return None
            current, to_target = edge[0], edge[1].then(to_target)
        return None


@dataclasses.dataclass(frozen=True)
class Mount:
    """A laser on the robot, as the suite's info needs it (metres, radians, base frame).

    :param yaw: where the laser's x axis points (0 ahead, counter-clockwise).
    :param upside_down: the laser's z axis points down: its angles run clockwise on the robot.
    :param tilt: the angle between the laser's scan plane and the base's horizontal plane
        (0 for a level laser, upright or upside down); the fan is taken as level.
    """

    x: float
    y: float
    z: float
    yaw: float
    upside_down: bool
    tilt: float

    def bearing(self, angle: float) -> float:
        """The robot-frame bearing of the laser's beam at ``angle`` (its own frame)."""
        return self.yaw - angle if self.upside_down else self.yaw + angle

    def close_to(self, other: Mount | None, *, metres: float = 1e-3, radians: float = 1e-3) -> bool:
        """Whether ``other`` is the same mount within ``metres`` and ``radians``."""
        if other is None or other.upside_down != self.upside_down:
            return False
        return (max(abs(self.x - other.x), abs(self.y - other.y), abs(self.z - other.z)) <= metres
                and abs(math.remainder(self.yaw - other.yaw, math.tau)) <= radians)


def mount_of(transform: Transform) -> Mount:
    """The mount of a laser whose frame is ``transform`` in the base frame."""
    matrix = transform.rotation.as_matrix()
    x, y, z = (float(v) for v in transform.translation)
    yaw = math.atan2(matrix[1, 0], matrix[0, 0])
    up = float(matrix[2, 2])
    return Mount(x, y, z, yaw, up < 0.0, math.acos(min(1.0, abs(up))))
