"""The five pose streams of Pluto's localization service and the values that travel on them.

Pluto 3 names the localModule's five interfaces and numbers them as the ``loc_proxy`` does; the
WURDE stream names are the seed's CORBA names (mapped to topics by :func:`wurde_core.stream_name`'s
reversible rule).  All five are of interface LocalizationPose:

=== ================================== ================================================================
 n  stream                             what
=== ================================== ================================================================
 0  ``Localization/Dead-Reckoning``    6-D pose of the robot centre since start; never jumps
 1  ``Localization/Laser_Dead-Reckoning`` 8-D pose of the laser (+ wrist pan, tilt) at the scan's
                                       time, with the covariance of the increment since the last scan
 2  ``Localization/Post_Pose``         input of improved poses (written as requests); cmdFlags < 0 a
                                       robot pose, otherwise a laser pose; cmdFlags is the setter
 3  ``Localization/Pose``              (0) adjusted by (2), covariance of the absolute pose
 4  ``Localization/Laser_Pose``        (1) adjusted by (2)
=== ================================== ================================================================

The setter (cmdFlags of 2, 3 and 4): 0 nobody, 1 poseModule, 2 slamModule, 3 slamModule saving,
negative: a robot pose was written (by a user, e.g. ``pose_i``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from wurde_core import Pose3D, Time
from wurde_core.structs import write_members

__all__ = ['DEAD_RECKONING', 'LASER_DEAD_RECKONING', 'LASER_POSE', 'NOBODY', 'POSE', 'POSE_SETTER',
           'POST_POSE', 'SLAM_SAVING', 'SLAM_SETTER', 'STREAMS', 'USER_SETTER', 'LocPose', 'read_pose',
           'write_members', 'write_pose']

STREAMS = ('Localization/Dead-Reckoning', 'Localization/Laser_Dead-Reckoning', 'Localization/Post_Pose',
           'Localization/Pose', 'Localization/Laser_Pose')
DEAD_RECKONING, LASER_DEAD_RECKONING, POST_POSE, POSE, LASER_POSE = range(5)

#: Setters (Pluto 3 and 7): cmdFlags of the Post_Pose, Pose and Laser_Pose streams.
NOBODY = 0
POSE_SETTER = 1
SLAM_SETTER = 2
SLAM_SAVING = 3
USER_SETTER = -1


@dataclasses.dataclass
class LocPose:
    """One pose of the localization service.

    ``pose`` is (x, y, z, theta, phi, psi) in m and rad: theta about z (up), then phi about y
    (left), then psi about x (forward), Pluto 3.  ``covariance`` is 3x3 over (x, y, theta).
    ``stamp`` is in seconds of the robot's clock (the odometry's / the scan's time).
    """

    pose: tuple[float, float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    pan: float = 0.0
    tilt: float = 0.0
    covariance: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((3, 3)))
    setter: int = NOBODY
    stamp: float = 0.0

    @property
    def xytheta(self) -> tuple[float, float, float]:
        return self.pose[0], self.pose[1], self.pose[3]

    def is_finite(self) -> bool:
        values = [*self.pose, self.pan, self.tilt, self.stamp]
        return all(math.isfinite(v) for v in values) and bool(np.all(np.isfinite(self.covariance)))


def write_pose(target: object, value: LocPose) -> None:
    """Fill a LocalizationPose data struct (or a request/info, whose members are Writable).

    :param target: the struct to fill; its ``timestamp``, if it has one, is set to ``value.stamp``.
    :param value: the pose, covariance and setter (written as cmdFlags).
    """
    x, y, z, theta, phi, psi = value.pose
    covariance = [float(c) for c in np.asarray(value.covariance, dtype=float).reshape(-1)]
    fields = {'pose': Pose3D(x, y, z, theta, phi, psi), 'pan': value.pan, 'tilt': value.tilt,
              'covariance': covariance, 'cmd_flags': int(value.setter)}
    write_members(target, fields)
    if hasattr(target, 'timestamp'):
        target.timestamp = Time(value.stamp)


def read_pose(source: object) -> LocPose:
    """A LocPose from a LocalizationPose data struct or request (Writable members).

    :param source: the struct; without a ``timestamp`` the stamp is 0, and a covariance that is not
        9 numbers is read as NaN.
    """
    def get(name: str) -> Any:
        member = getattr(source, name)
        return member.get_value() if hasattr(member, 'get_value') else member

    pose = get('pose')
    covariance = np.asarray(list(get('covariance') or []), dtype=float)
    cov = covariance.reshape(3, 3) if covariance.size == 9 else np.full((3, 3), math.nan)
    stamp = source.timestamp.get_seconds() if hasattr(source, 'timestamp') else 0.0
    return LocPose(pose=(pose.x(), pose.y(), pose.z(), pose.theta(), pose.phi(), pose.psi()),
                   pan=float(get('pan')), tilt=float(get('tilt')), covariance=cov,
                   setter=int(get('cmd_flags')), stamp=stamp)
