"""The simulator's people: moving obstacles, each a body walking a :class:`~.walk.Walk`.

A person is a disc (``radius``) or a box (``length`` along the walking direction, ``width``
across it) of some ``height``, standing on the floor.  Where everyone is at a stamp is a pure
function of the stamp (:mod:`.walk`), so every dummy computes the same people on its own:
:meth:`People.shapes_at` gives the bodies at a stamp as :class:`~.shapes.Shapes`, which the
world's ray casting, the base's sweep and the bumpers use (:class:`~.world.World` holds the
people).  People walk through one another and through the robot (their walks are scripted; they
neither yield nor push), and the laser and the sonars see a person whatever its height above
theirs (the config refuses one shorter than a sensor's height, :mod:`.config`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator

import numpy as np
from numpy.typing import NDArray

from .shapes import Shapes
from .walk import Walk

__all__ = ['Body', 'People', 'Person']


@dataclasses.dataclass(frozen=True)
class Body:
    """A person's shape: a disc of ``radius``, or a box of ``length`` x ``width`` (m), and a
    ``height`` (m).  A box's length lies along the walking direction.

    :raises ValueError: a size not above zero or not finite, or both a radius and a box size.
    """

    height: float = 1.75
    radius: float = 0.0
    length: float = 0.0
    width: float = 0.0

    def __post_init__(self) -> None:
        sizes = (self.height, self.radius, self.length, self.width)
        if not all(math.isfinite(v) and v >= 0.0 for v in sizes) or self.height <= 0.0:
            raise ValueError(f'a body needs finite sizes and a height above zero, got {sizes}')
        box = self.length > 0.0 and self.width > 0.0
        if box == (self.radius > 0.0) or (not box and (self.length or self.width)):
            raise ValueError('a body is a disc (radius) or a box (length and width), not both or neither')

    @property
    def is_box(self) -> bool:
        return self.radius == 0.0

    @property
    def half_length(self) -> float:
        """Reach ahead of and behind the centre along the walking direction (m)."""
        return self.length / 2 if self.is_box else self.radius

    @property
    def half_width(self) -> float:
        """Reach to each side of the walking direction (m)."""
        return self.width / 2 if self.is_box else self.radius

    @property
    def reach(self) -> float:
        """The farthest the body reaches from its centre in any direction (m): what a turn on
        the spot sweeps."""
        return math.hypot(self.length / 2, self.width / 2) if self.is_box else self.radius

    def describe(self) -> str:
        kind = (f'box {self.length:g} x {self.width:g} m' if self.is_box else f'disc r {self.radius:g} m')
        return f'{kind}, {self.height:g} m tall'


@dataclasses.dataclass(frozen=True)
class Person:
    """A named body on a walk."""

    name: str
    body: Body
    walk: Walk

    def pose_at(self, stamp: float) -> tuple[float, float, float]:
        """``(x, y, heading)`` of the body's centre at ``stamp`` (map frame)."""
        return self.walk.pose_at(stamp)


@dataclasses.dataclass(frozen=True)
class People:
    """Everyone in the world, in the config's order; a person's index is its id in
    :class:`~.shapes.Shapes` and in contacts."""

    members: tuple[Person, ...] = ()

    def __len__(self) -> int:
        return len(self.members)

    def __iter__(self) -> Iterator[Person]:
        return iter(self.members)

    def __getitem__(self, index: int) -> Person:
        return self.members[index]

    def poses_at(self, stamp: float) -> NDArray:
        """``(P, 3)``: every person's ``x, y, heading`` at ``stamp``."""
        if not self.members:
            return np.empty((0, 3))
        return np.array([person.pose_at(stamp) for person in self.members])

    def shapes_at(self, stamp: float) -> Shapes:
        """Everyone's body at ``stamp``, each shape's id the person's index."""
        poses = self.poses_at(stamp)
        discs, disc_ids, boxes, box_ids = [], [], [], []
        for index, (person, (x, y, heading)) in enumerate(zip(self.members, poses)):
            body = person.body
            if body.is_box:
                boxes.append((x, y, heading, body.length / 2, body.width / 2))
                box_ids.append(index)
            else:
                discs.append((x, y, body.radius))
                disc_ids.append(index)
        return Shapes(discs, boxes, disc_ids=disc_ids, box_ids=box_ids)
