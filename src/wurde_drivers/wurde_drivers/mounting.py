"""Where a device sits on the robot: one attribute set for every device config (REP-103/105).

A device's ``<device>`` element (``laser-config``, ``dmu-config``, ``gps-config``,
``wrist-config``, ``ptu-config``) and the dummies' elements of ``sim-config.xml`` (``<laser>``,
``<dmu>``, ``<gps>``, ``<wrist>``) take the same optional attributes, all relative to
``base_link`` (x forward, y left, z up from the floor, REP-103):

============== ======= ===================================================================
attribute      default meaning
============== ======= ===================================================================
``mount-x``    0       m forward of the robot's centre
``mount-y``    0       m to the left
``mount-z``    0       m above the floor (the laser's default is 0.4, as before)
``mount-yaw``  0       rad, counter-clockwise: where the device's x axis points (pan/tilt
                       units only: their pan 0; the other devices report in the robot's axes)
============== ======= ===================================================================

The module of that device publishes the mounting as a static transform ``base_link`` → its frame
on ``/tf_static`` (:mod:`wurde_drivers.ros_std_frames`). Pure Python, no rclpy.
"""

from __future__ import annotations

import dataclasses

from .xml_config import Attributes

__all__ = ['MOUNT_ATTRIBUTES', 'MOUNT_XYZ', 'Mounting', 'read_mounting']

#: The optional attributes of a device that reports in the robot's axes (no yaw).
MOUNT_XYZ = ('mount-x', 'mount-y', 'mount-z')
#: The optional attributes of a device with its own heading (a pan/tilt unit).
MOUNT_ATTRIBUTES = (*MOUNT_XYZ, 'mount-yaw')


@dataclasses.dataclass(frozen=True)
class Mounting:
    """A device's pose on the robot: metres and radians in ``base_link``."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    yaw: float = 0.0


def read_mounting(attrs: Attributes, *, z: float = 0.0) -> Mounting:
    """The ``mount-*`` attributes of ``attrs`` (those it does not allow read as their defaults).

    :param attrs: the element's attributes, ``mount-*`` among the allowed ones.
    :param z: the default height (the laser's is 0.4 m).
    :raises ConfigError: a value that is not a finite number, naming file and line.
    """
    return Mounting(x=attrs.number('mount-x', 0.0), y=attrs.number('mount-y', 0.0),
                    z=attrs.number('mount-z', z), yaw=attrs.number('mount-yaw', 0.0))
