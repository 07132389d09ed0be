"""How uncertain an odometry increment is: the covariance the Kalman filter's predict step needs.

Pluto's Laser_Dead-Reckoning stream gives "the estimated error covariance in the difference
between this pose and the previous one" (Pluto 3); the localModule computes it with
:func:`increment_covariance` and moves it to the laser with :func:`laser_increment`.

The model is the simulated base's (``wurde_drivers.sim.robot.OdometryNoise``), with errors that
add up along the path: over an increment that drives ``d`` metres and turns ``dtheta`` radians,

- distance: variance ``trans² |d|`` (``trans``: standard deviation per metre, a fraction);
- heading: variance ``rot² |dtheta|`` (``rot``: per radian turned, a fraction);
- drift: a heading error of ``drift`` rad per metre driven (one wheel a little smaller).  It is
  systematic, but the filter can only take noise, so it enters as variance
  ``drift² |d| max(1, |d|)``: at least the drift itself (``drift |d|``) on increments over a
  metre, and on a run of short increments the accumulated drift stays within one standard
  deviation for the first metre, by which time the laser has corrected the heading;
- a floor (``floor_xy`` m, ``floor_theta`` rad standard deviation per increment) so the
  covariance is never zero, not even standing still.

The errors in distance and heading are mapped to ``(x, y, theta)`` through the increment's arc:
``(d cos(dtheta/2), d sin(dtheta/2), dtheta)``.  Only the measured increment is known, so an
increment the odometry under-reports gets a slightly small covariance; the pose filter's
widened gates take such slips.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .geometry import compose, compose_jacobians, inverse

__all__ = ['OdometryNoiseModel', 'increment_covariance', 'laser_increment']


@dataclasses.dataclass(frozen=True)
class OdometryNoiseModel:
    """Tunables of :func:`increment_covariance` (see the module's description)."""

    #: Standard deviation of the distance error per metre driven, a fraction [0.05].
    trans: float = 0.05
    #: Standard deviation of the heading error per radian turned, a fraction [0.05].
    rot: float = 0.05
    #: Heading error in rad per metre driven [0.02].
    drift: float = 0.02
    #: m and rad: standard deviations every increment gets at least [0.001, 0.001].
    floor_xy: float = 0.001
    floor_theta: float = 0.001

    def __post_init__(self) -> None:
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{field.name} must be finite and not negative, not {value}')


def increment_covariance(increment: ArrayLike,
                         model: OdometryNoiseModel = OdometryNoiseModel()) -> NDArray:
    """The 3x3 covariance of an odometry ``increment``.

    :param increment: ``(dx, dy, dtheta)`` in the frame it started in (metres, radians; driving
        backwards has ``dx < 0``).
    :param model: the noise model: translation, rotation and drift factors and a floor.
    """
    dx, dy, dtheta = np.asarray(increment, dtype=np.float64).reshape(3).tolist()
    distance = math.copysign(math.hypot(dx, dy), dx)
    travel = abs(distance)
    var_distance = model.trans ** 2 * travel
    var_heading = model.rot ** 2 * abs(dtheta) + model.drift ** 2 * travel * max(1.0, travel)
    half = 0.5 * dtheta
    c, s = math.cos(half), math.sin(half)
    jac = np.array([[c, -0.5 * distance * s],
                    [s, 0.5 * distance * c],
                    [0.0, 1.0]])
    cov = (jac * np.array([var_distance, var_heading])) @ jac.T
    cov += np.diag([model.floor_xy ** 2, model.floor_xy ** 2, model.floor_theta ** 2])
    return 0.5 * (cov + cov.T)


def laser_increment(increment: ArrayLike, covariance: ArrayLike,
                    mount: ArrayLike) -> tuple[NDArray, NDArray]:
    """A robot increment and its covariance as the increment of a sensor mounted at ``mount``.

    The robot moves by ``u`` (in its previous frame); a sensor at ``mount`` ``(x, y, theta)`` on
    the robot then moves by ``⊖mount ⊕ u ⊕ mount`` in its own previous frame.

    :param increment: the robot's ``(dx, dy, dtheta)`` in its previous frame.
    :param covariance: its 3x3 covariance.
    :param mount: the sensor's pose ``(x, y, theta)`` on the robot.
    :returns: ``(increment, covariance)`` of the sensor.
    """
    u = np.asarray(increment, dtype=np.float64).reshape(3)
    m = np.asarray(mount, dtype=np.float64).reshape(3)
    cov = np.asarray(covariance, dtype=np.float64).reshape(3, 3)
    inner = compose(u, m)
    j_u, _ = compose_jacobians(u, m)
    back = inverse(m)
    _, j_inner = compose_jacobians(back, inner)
    jac = j_inner @ j_u
    out = jac @ cov @ jac.T
    return compose(back, inner), 0.5 * (out + out.T)
