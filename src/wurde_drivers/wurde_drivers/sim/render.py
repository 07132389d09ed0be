"""A camera's view of the simulated world: walls drawn column by column from the raycaster.

Each image column looks along one ray (a pinhole camera with the given horizontal field of view);
the wall it meets at distance ``d`` fills the rows between the floor and the wall's top seen at
the perpendicular distance, shaded darker with distance. Above is a plain ceiling, below a plain
floor; a column that meets no wall within ``max_range`` shows none. Enough for the simulated
robot's eyes (the vision operators, the Eye viewer), not a renderer. Pure numpy: no ROS.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from .world import World

__all__ = ['CEILING', 'FLOOR', 'View', 'column_angles', 'render']

#: BGR colours (OpenCV's order).
CEILING = (200, 180, 160)
FLOOR = (60, 90, 110)
WALL = np.array((210, 210, 220), np.float64)


@dataclasses.dataclass(frozen=True)
class View:
    """The camera: image size, horizontal field of view (rad), its height above the floor and
    the walls' height (m), and the farthest wall it sees (m)."""

    width: int = 320
    height: int = 240
    field_of_view: float = math.radians(60.0)
    camera_height: float = 1.0
    wall_height: float = 2.0
    max_range: float = 20.0

    @property
    def focal(self) -> float:
        """Focal length in pixels."""
        return (self.width / 2.0) / math.tan(self.field_of_view / 2.0)


def column_angles(view: View) -> NDArray[np.float64]:
    """The angle of each column's ray from the optical axis (rad; left of the axis positive)."""
    offsets = view.width / 2.0 - (np.arange(view.width) + 0.5)
    return np.arctan2(offsets, view.focal)


def render(world: World, x: float, y: float, theta: float,
           view: View) -> tuple[NDArray[np.uint8], NDArray[np.float64]]:
    """The BGR image seen from ``(x, y)`` looking along ``theta``, and each column's distance
    to its wall (``inf``: none within range)."""
    offsets = column_angles(view)
    distance = world.raycast((x, y), theta + offsets, view.max_range)
    distance = np.where(distance >= view.max_range, np.inf, distance)
    depth = np.maximum(distance * np.cos(offsets), 1e-3)             # perpendicular distance
    horizon = view.height / 2.0
    top = horizon - view.focal * (view.wall_height - view.camera_height) / depth
    bottom = horizon + view.focal * view.camera_height / depth
    rows = np.arange(view.height)[:, None] + 0.5
    image = np.empty((view.height, view.width, 3), np.uint8)
    image[:] = CEILING
    image[rows[:, 0] >= horizon] = FLOOR
    wall = (rows >= top[None, :]) & (rows < bottom[None, :])
    shade = np.clip(1.0 - np.nan_to_num(distance, posinf=view.max_range) / (1.5 * view.max_range), 0.2, 1.0)
    colours = (WALL[None, :] * shade[:, None]).astype(np.uint8)      # one colour per column
    image[wall] = np.broadcast_to(colours[None, :, :], image.shape)[wall]
    return image, distance
