"""A pan/tilt unit's state as ``sensor_msgs/JointState`` on ``/S/joint_states``.

The wrist (ActuatorState: position and velocity [pan, tilt]) and the PTU (PTUnit: pan, tilt and
their velocities) both publish two joints named after the unit's frame
(:func:`wurde_drivers.ros_std_frames.frame_of`): ``<frame>_pan`` and ``<frame>_tilt``, radians
and rad/s (REP-103); no effort (the units do not measure it). The unit's base frame ``<frame>``
(where pan and tilt are 0) hangs off ``base_link`` at its configured mounting, published on
``/tf_static`` by :func:`pan_tilt_standard`.
"""

from __future__ import annotations

from typing import Any

from sensor_msgs.msg import JointState
from wurde_core.ros_messages import set_stamp

from .mounting import Mounting
from .ros_std import std_topic, watched
from .ros_std_frames import StaticFrames, frame_of

__all__ = ['JointStatePublisher', 'joint_names', 'pan_tilt_standard']


def joint_names(stream: str) -> list[str]:
    """``[<frame>_pan, <frame>_tilt]`` of the unit on ``stream``."""
    frame = frame_of(stream)
    return [f'{frame}_pan', f'{frame}_tilt']


class JointStatePublisher:
    """``/S/joint_states``: pan and tilt positions and velocities of the unit on ``stream``."""

    def __init__(self, node: Any, stream: str) -> None:
        self.publisher = node.create_publisher(JointState, std_topic(stream, 'joint_states'), 10)
        self.msg = JointState()
        self.msg.name = joint_names(stream)

    def publish(self, *, pan: float, tilt: float, pan_velocity: float, tilt_velocity: float,
                stamp: float) -> None:
        if not watched(self.publisher):
            return
        msg = self.msg
        set_stamp(msg, stamp)
        msg.position = [float(pan), float(tilt)]
        msg.velocity = [float(pan_velocity), float(tilt_velocity)]
        self.publisher.publish(msg)


def pan_tilt_standard(node: Any, stream: str, mount: Mounting) -> JointStatePublisher:
    """The standard side of a pan/tilt module: its base frame at ``mount`` on ``/tf_static``
    (now, once) and the publisher of its joint states."""
    StaticFrames(node).set([(frame_of(stream), mount)])
    return JointStatePublisher(node, stream)
