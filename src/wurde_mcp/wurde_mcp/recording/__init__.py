"""Recording ROS 2 topics to rosbag2 bags (MCAP) and replaying them (Mobotware's replay; issue 13):
the bytes as they travelled (CDR), each channel with its full message definition and its
publishers' QoS as rosbag2 keeps them, so any MCAP or rosbag2 reader (Foxglove, the ``mcap`` CLI,
``ros2 bag``, :mod:`mcap_ros2`, rosbags) decodes them; ``replay`` plays rosbag2's bags back."""

from .schema import message_definition

__all__ = ['message_definition']
