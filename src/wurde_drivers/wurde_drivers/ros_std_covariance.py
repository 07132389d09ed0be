"""Covariances of the standard messages, from each device's noise figures (pure Python, no rclpy).

Every figure has a named source where it is set: the simulator's noise settings
(``sim-config.xml``) for the dummies, the device's documented accuracy (or, where no manual is at
hand, a stated assumption) for the real drivers. No covariance is published as all zeros: a zero
variance claims perfect knowledge, which estimators (robot_localization, Nav2's AMCL) cannot
fuse, so :data:`MIN_VARIANCE` is added to every measured variance. Axes a device does not measure get
:data:`UNKNOWN_VARIANCE` (as pluto_nav's localization does for z, roll and pitch).

- :class:`OdometryCovariance`: the 2-D dead-reckoning error propagated
  step by step (pose) and its rate over one step (twist), for ``nav_msgs/Odometry``;
- :class:`ImuNoise` → :class:`ImuCovariance`: white noise on rates and accelerations, reduced by
  the DMU's first-order low-pass, and the heading's random walk, for ``sensor_msgs/Imu``;
- :func:`fix_covariance`: ``sensor_msgs/NavSatFix`` from HDOP and fix quality (APPROXIMATED).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ['MIN_VARIANCE', 'UNKNOWN_VARIANCE', 'ImuCovariance', 'ImuNoise', 'OdometryCovariance',
           'fix_covariance', 'lowpass_variance_factor']

#: The least variance published (1 mm, 1 mrad standard deviation): never "perfectly known".
MIN_VARIANCE = 1e-6
#: Variance of an axis the device does not measure ("unknown", as pluto_nav.ros_std).
UNKNOWN_VARIANCE = 1e6


class OdometryCovariance:
    """Dead reckoning's (x, y, yaw) covariance, grown by each odometry sample's motion.

    First-order propagation (the Jacobians of the unicycle step): between two samples the
    distance ``ds`` and turn ``dtheta`` get variances ``trans² |ds|`` and
    ``rot² |dtheta| + (drift ds)²``, as the simulator draws them
    (:class:`wurde_drivers.sim.robot.OdometryNoise`).

    :param trans: standard deviation of the distance error per sqrt(metre) driven.
    :param rot: of the heading error per sqrt(radian) turned.
    :param drift: heading error in rad per metre (a bias the consumer does not know, counted
        as noise of that size).
    """

    def __init__(self, *, trans: float, rot: float, drift: float) -> None:
        self.trans, self.rot, self.drift = trans, rot, drift
        self.cov = np.zeros((3, 3))
        self._last: tuple[float, float, float, float] | None = None
        self.twist = np.zeros(2)

    def update(self, x: float, y: float, theta: float, stamp: float) -> None:
        """Take the next odometry pose (m, rad) at ``stamp`` (s)."""
        last, self._last = self._last, (x, y, theta, stamp)
        if last is None:
            return
        ds = math.hypot(x - last[0], y - last[1])
        dtheta = abs(math.remainder(theta - last[2], math.tau))   # across ±pi: the short way
        q = np.diag([self.trans ** 2 * ds, self.rot ** 2 * dtheta + (self.drift * ds) ** 2])
        heading = last[2]
        f = np.array([[1.0, 0.0, -ds * math.sin(heading)], [0.0, 1.0, ds * math.cos(heading)],
                      [0.0, 0.0, 1.0]])
        g = np.array([[math.cos(heading), 0.0], [math.sin(heading), 0.0], [0.0, 1.0]])
        self.cov = f @ self.cov @ f.T + g @ q @ g.T
        dt = stamp - last[3]
        if dt > 0:
            self.twist = np.diag(q) / dt ** 2

    def pose6(self) -> list[float]:
        """The row-major 6x6 pose covariance (x, y, z, roll, pitch, yaw)."""
        full = np.diag([MIN_VARIANCE, MIN_VARIANCE, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE,
                        UNKNOWN_VARIANCE, MIN_VARIANCE])
        index = [0, 1, 5]
        full[np.ix_(index, index)] += self.cov
        return [float(v) for v in full.reshape(-1)]

    def twist6(self) -> list[float]:
        """The row-major 6x6 twist covariance (vx, vy, vz, wx, wy, wz): vx and wz measured."""
        full = np.diag([MIN_VARIANCE, MIN_VARIANCE, UNKNOWN_VARIANCE, UNKNOWN_VARIANCE,
                        UNKNOWN_VARIANCE, MIN_VARIANCE])
        full[0, 0] += self.twist[0]
        full[5, 5] += self.twist[1]
        return [float(v) for v in full.reshape(-1)]


@dataclasses.dataclass(frozen=True)
class ImuNoise:
    """White noise standard deviations of a DMU's raw sample, in the robot's axes.

    ``rate`` rad/s on each angular rate, ``accel`` m/s² on each acceleration, ``angle`` rad on
    roll and pitch (the sensor's own gravity-aided angles).
    """

    rate: float = 0.0
    accel: float = 0.0
    angle: float = 0.0


def lowpass_variance_factor(dt: float, tau: float) -> float:
    """The variance of white noise after ``y += a (x - y)`` with ``a = 1 - exp(-dt/tau)``, per
    unit of input variance: ``a / (2 - a)`` (the DMU filter, :class:`wurde_drivers.dmu.filter`)."""
    a = 1.0 - math.exp(-dt / tau) if tau > 0 else 1.0
    return a / (2.0 - a)


class ImuCovariance:
    """The three 3x3 covariances of ``sensor_msgs/Imu`` for the filtered DMU state.

    :param noise: the raw sample's noise.
    :param tau: the low-pass's time constant in s (0: unfiltered).
    """

    def __init__(self, noise: ImuNoise, tau: float) -> None:
        self.noise = noise
        self.tau = tau
        self.yaw_variance = 0.0
        self._last: float | None = None
        self._factor = 1.0

    def update(self, stamp: float) -> None:
        """Take the next sample's stamp: the heading integrates one more step of rate noise."""
        last, self._last = self._last, stamp
        if last is None or stamp <= last:
            return
        dt = stamp - last
        self._factor = lowpass_variance_factor(dt, self.tau)
        self.yaw_variance += (self.noise.rate * dt) ** 2

    @staticmethod
    def _diag(*variances: float) -> list[float]:
        v = [MIN_VARIANCE + x for x in variances]
        return [v[0], 0.0, 0.0, 0.0, v[1], 0.0, 0.0, 0.0, v[2]]

    def orientation(self) -> list[float]:
        """Roll, pitch (the sensor's angles) and yaw (integrated since the start)."""
        angle = self.noise.angle ** 2
        return self._diag(angle, angle, self.yaw_variance)

    def angular_velocity(self) -> list[float]:
        rate = self.noise.rate ** 2 * self._factor
        return self._diag(rate, rate, rate)

    def linear_acceleration(self) -> list[float]:
        accel = self.noise.accel ** 2 * self._factor
        return self._diag(accel, accel, accel)


#: Estimated position error (m, 1 sigma at HDOP 1) per GGA fix quality: the defaults of
#: ros-drivers/nmea_navsat_driver (``epe_quality0..9``), the ROS NMEA driver's own table.
#: Qualities it has no figure for (3 PPS, 6 dead reckoning, 7 manual, 8 simulation) count as
#: plain GPS (3) or as no fix (6-8).
EPE_M = {0: 1_000_000.0, 1: 4.0, 2: 0.1, 3: 4.0, 4: 0.02, 5: 4.0, 9: 3.0}
NO_FIX_EPE_M = EPE_M[0]


def fix_covariance(quality: int, hdop: float) -> list[float]:
    """``NavSatFix.position_covariance`` (east, north, up; m²) as nmea_navsat_driver computes it:
    horizontal ``(hdop * epe)²``, vertical ``(2 * hdop * epe)²`` (plus :data:`MIN_VARIANCE`)."""
    epe = EPE_M.get(int(quality), NO_FIX_EPE_M)
    h = hdop if math.isfinite(hdop) and hdop > 0 else 1.0
    horizontal = MIN_VARIANCE + (h * epe) ** 2
    vertical = MIN_VARIANCE + (2 * h * epe) ** 2
    return [horizontal, 0.0, 0.0, 0.0, horizontal, 0.0, 0.0, 0.0, vertical]
