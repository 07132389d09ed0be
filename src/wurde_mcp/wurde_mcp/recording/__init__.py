"""Recording ROS 2 topics to MCAP and replaying them (Mobotware's replay; issue 13): the bytes as
they travelled (CDR), each channel with its full message definition, so any MCAP reader (Foxglove,
the ``mcap`` CLI, ``ros2 bag``, :mod:`mcap_ros2`) decodes them."""

from .schema import message_definition

__all__ = ['message_definition']
