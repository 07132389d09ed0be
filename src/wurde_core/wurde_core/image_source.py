"""``ImageSource``: the guide's class over the ImageTransport interface (WURDE 3.4.9, 7.8).

A supplier (the VisionModule's ImagePublisher, a camera driver, a test pattern) sets one image
with :meth:`ImageSource.set_image` and sends it with ``publish_data`` (or both at once with
:meth:`ImageSource.publish_image`); a consumer (the Eye) reads the current event's pixel bytes
with :meth:`ImageSource.pixels` without copying them. The pixel bytes travel as the message's
``uint8[]`` array and are handed over whole (no per-byte Python conversion): a 320x240 RGB image
is 230 kB.
"""

from __future__ import annotations

import array

from .robot_object import RobotObject

__all__ = ['ImageSource']


class ImageSource(RobotObject, interface='ImageTransport'):
    """Images on an ImageTransport stream: ``publish_image(...)``, ``pixels()``."""

    def set_image(self, width: int, height: int, encoding: str, pixels: bytes | bytearray | memoryview,
                  *, step: int | None = None, frame_index: int | None = None) -> None:
        """Put one image into ``data``.

        :param width: pixels per row.
        :param height: rows.
        :param encoding: ImageTransport's encoding name (mono8, rgb8, yuv422, yuv24), which
            fixes the layout.
        :param pixels: the bytes, row by row (copied into the message).
        :param step: bytes per row; None: ``len(pixels) // height``.
        :param frame_index: the frame's number; None: one more than the last in ``data``.
        """
        data = self.data
        data.width, data.height, data.encoding = int(width), int(height), str(encoding)
        data.step = int(step) if step is not None else len(pixels) // max(1, int(height))
        data.frame_index = int(frame_index) if frame_index is not None else data.frame_index + 1
        self.data.ros_message().data = array.array('B', bytes(pixels))

    def publish_image(self, width: int, height: int, encoding: str,
                      pixels: bytes | bytearray | memoryview, *, step: int | None = None,
                      frame_index: int | None = None) -> bool:
        """:meth:`set_image`, then ``publish_data()``.

        :param width: pixels per row.
        :param height: rows.
        :param encoding: ImageTransport's encoding name (mono8, rgb8, yuv422, yuv24).
        :param pixels: the bytes, row by row.
        :param step: bytes per row; None: ``len(pixels) // height``.
        :param frame_index: the frame's number; None: one more than the last.
        :returns: whether it was sent (False when the run state lets no data flow).
        """
        self.set_image(width, height, encoding, pixels, step=step, frame_index=frame_index)
        return self.publish_data()

    def pixels(self) -> memoryview:
        """The pixel bytes of the image in ``data`` (the last event loaded), not copied."""
        return memoryview(self.data.ros_message().data).cast('B')
