"""ImagePublisher: a camera's frames as an ImageTransport stream and ``sensor_msgs/Image``
(WURDE guide 7.2.3).

Options: ``format`` (gray, rgb, yuv24 or yuv422; default gray, as the guide), and ours:
``stream`` (the ImageTransport stream name; default the operator's name). Any resolution (the
guide's was 320x240 only).

- ImageTransport ``stream``: data is one image (width, height, ROS encoding, step, the camera's
  frame index, pixel bytes; stamped with the frame's time, :mod:`..formats`); info says the
  camera, format, size and the measured frame rate, sent at the first frame, when the size
  changes and every :data:`INFO_EVERY` frames.
- ``/<stream>/image_raw`` (``sensor_msgs/Image``, frame ``<camera>``, REP-103 naming as the other
  standard mirrors): the same pixels and encoding — but yuv24, which ROS does not name, goes
  there as ``rgb8`` so ROS viewers can show it.
"""

from __future__ import annotations

import array
from collections.abc import Mapping

from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Image
from wurde_core import Time
from wurde_core.interfaces import ImageTransport
from wurde_core.ros_messages import set_stamp
from wurde_idl.errors import ConfigError

from ...ros_std import std_topic
from ...ros_std_frames import frame_of
from ..camera import Frame
from ..formats import FORMATS, Encoded, encode
from ..operator import Operator, OperatorContext
from ..vision_config import OperatorSpec

__all__ = ['INFO_EVERY', 'ImagePublisher', 'image_message']

#: Frames between two info updates (the measured rate).
INFO_EVERY = 50
_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.RELIABLE)


def image_message(encoded: Encoded, stamp: float, frame_id: str) -> Image:
    """A ``sensor_msgs/Image`` of ``encoded``."""
    msg = Image()
    set_stamp(msg, stamp)
    msg.header.frame_id = frame_id
    msg.height, msg.width = encoded.height, encoded.width
    msg.encoding, msg.step, msg.is_bigendian = encoded.encoding, encoded.step, 0
    msg.data = array.array('B', encoded.data)
    return msg


class ImagePublisher(Operator):
    OPTIONS = {'format': 'gray', 'stream': ''}

    def __init__(self, spec: OperatorSpec) -> None:
        super().__init__(spec)
        self.format = 'gray'
        self.stream: ImageTransport | None = None
        self._image_pub = None
        self._stream_name = ''
        self._size = (0, 0)
        self._first_stamp = 0.0
        self.published = 0
        self.configure()

    def configure(self) -> None:
        if self.options['format'] not in FORMATS:
            raise ConfigError(self.spec.path, self.spec.line,
                              f'operator "{self.name}": format "{self.options["format"]}" is not one '
                              f'of {", ".join(FORMATS)}')
        if self.stream is not None and self.stream_name != self._stream_name:
            raise ConfigError(self.spec.path, self.spec.line, f'operator "{self.name}": the stream '
                              'cannot change while the module runs; restart it')
        if self.options['format'] != self.format:
            self.format = self.options['format']
            self._size = (0, 0)   # the info says the new format at the next frame

    @property
    def stream_name(self) -> str:
        return self.options['stream'] or self.name

    def setup(self, context: OperatorContext) -> None:
        super().setup(context)
        self._stream_name = self.stream_name
        self.stream = ImageTransport(self.stream_name)
        self.stream.set_auto_timestamp(False)   # stamped with the frame's time
        context.manager.register_supplier(self.stream)
        self._image_pub = context.manager.node.create_publisher(
            Image, std_topic(self.stream_name, 'image_raw'), _QOS)

    def _publish_info(self, frame: Frame) -> None:
        assert self.stream is not None
        info = self.stream.info
        span = frame.stamp - self._first_stamp
        info.camera.set_value(frame.camera)
        info.format.set_value(self.format)
        info.width.set_value(frame.width)
        info.height.set_value(frame.height)
        info.frame_rate.set_value(self.published / span if span > 0 and self.published else 0.0)
        self.stream.publish_info()

    def process(self, frames: Mapping[str, Frame]) -> None:
        assert self.stream is not None and self._image_pub is not None
        frame = self.main(frames)
        try:
            encoded = encode(frame.image, self.format)
        except ValueError as error:
            self.context.logger.warn(f'{self.name}: frame {frame.index} not published: {error}')
            return
        if self.published == 0:
            self._first_stamp = frame.stamp
        if (frame.width, frame.height) != self._size or self.published % INFO_EVERY == 0:
            self._size = (frame.width, frame.height)
            self._publish_info(frame)
        data = self.stream.data
        data.width, data.height = encoded.width, encoded.height
        data.encoding, data.step, data.frame_index = encoded.encoding, encoded.step, frame.index
        data.timestamp = Time(frame.stamp)
        # The pixels go straight into the message: wurde_core's element-wise copy of a list is
        # far too slow for a quarter of a megabyte per frame.
        data.ros_message().data = array.array('B', encoded.data)
        self.stream.publish_data()
        standard = encoded if self.format != 'yuv24' else encode(frame.image, 'rgb')
        self._image_pub.publish(image_message(standard, frame.stamp, frame_of(frame.camera)))
        self.published += 1

