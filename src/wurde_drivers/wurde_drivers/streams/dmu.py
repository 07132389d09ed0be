"""The streams of a DMU module, shared by the Crossbow DMU driver and the dummy DMU (Pluto 8.2).

A DMU module named ``N`` supplies two DMUState streams, as Pluto's dmuModule had two interfaces:

- ``N/Raw`` — DMUraw_state: the sensor's data in the robot frame (x forward, y left, z up):
  pitch and roll, instantaneous angular rates and accelerations; theta is 0 (the sensor gives no
  heading). Stamped when the sample was read.
- ``N`` — DMUstate: rates and accelerations low-pass filtered, theta the heading integrated from
  the filtered z rate since the start, stamped earlier by the filter's delay
  (:class:`wurde_drivers.dmu.filter.DmuFilter`). Its info carries the cut-off and the delay.

The filtered state also goes out as ``sensor_msgs/Imu`` on ``/N/imu`` (:mod:`wurde_drivers.ros_std`),
in frame ``N`` (axes the robot's), with covariances from the module's noise figures, and the
unit's mounting ``base_link`` → ``N`` on ``/tf_static``.
"""

from __future__ import annotations

from wurde_core import CommsManager, Time
from wurde_core.interfaces import DMUState

from ..dmu.filter import DmuFilter, FilteredState
from ..dmu.sample import MOTION_FIELDS, Inertial
from ..mounting import Mounting
from ..ros_std import ImuPublisher
from ..ros_std_covariance import ImuNoise
from ..ros_std_frames import StaticFrames, frame_of

__all__ = ['DmuStreams']


class DmuStreams:
    """Suppliers of one DMU and its filter; feed raw samples to :meth:`publish`."""

    def __init__(self, name: str, cutoff_hz: float, *, noise: ImuNoise, mount: Mounting) -> None:
        """:param noise: the raw sample's noise (the module names the figures' source).
        :param mount: where the unit sits (translation only: the data are in the robot's axes)."""
        self.name = name
        self.noise = noise
        self.mount = Mounting(mount.x, mount.y, mount.z)
        self.filter = DmuFilter(cutoff_hz)
        self.raw = DMUState(f'{name}/Raw')
        self.state = DMUState(name)
        for obj in (self.raw, self.state):
            obj.set_auto_timestamp(False)
        self._imu: ImuPublisher | None = None
        self._frames: StaticFrames | None = None

    def register(self, manager: CommsManager) -> None:
        manager.register_supplier(self.raw)
        manager.register_supplier(self.state)
        if '/' not in self.name:
            self._imu = ImuPublisher(manager.node, self.name, noise=self.noise, tau=self.filter.tau)
        self._frames = StaticFrames(manager.node)
        self._frames.set([(frame_of(self.name), self.mount)])

    def publish_info(self) -> None:
        for obj, filtered in ((self.raw, False), (self.state, True)):
            obj.info.filtered.set_value(filtered)
            obj.info.cutoff_frequency.set_value(self.filter.cutoff_hz if filtered else 0.0)
            obj.info.filter_delay.set_value(self.filter.filter_delay if filtered else 0.0)
            obj.publish_info()

    def publish(self, sample: Inertial, stamp: float, *, raw: bool = True, filtered: bool = True) -> FilteredState:
        """Filter ``sample`` (robot frame) and publish the raw and/or the filtered state."""
        state = self.filter.update(sample, stamp)
        if raw:
            d = self.raw.data
            d.theta = 0.0
            d.phi = float(sample.pitch or 0.0)
            d.psi = float(sample.roll or 0.0)
            for field in MOTION_FIELDS:
                setattr(d, field, float(getattr(sample, field)))
            d.timestamp = Time(stamp)
            self.raw.publish_data()
        if filtered:
            d = self.state.data
            d.theta = state.theta
            d.phi = float(state.phi or 0.0)
            d.psi = float(state.psi or 0.0)
            for field in MOTION_FIELDS:
                setattr(d, field, getattr(state, field))
            d.timestamp = Time(state.stamp)
            self.state.publish_data()
            if self._imu is not None:
                self._imu.publish(state, state.stamp)
        return state
