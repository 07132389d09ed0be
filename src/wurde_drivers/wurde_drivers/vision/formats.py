"""Pixel formats of the ImagePublisher (WURDE guide 7.2.3): pure conversions, no ROS.

A camera's frame is an OpenCV BGR image (``H x W x 3``, uint8). :func:`encode` turns it into the
bytes of one of the guide's formats with the ROS encoding name the ImageTransport interface uses
(and ``sensor_msgs/Image`` understands):

======== ============ ========= =============================================================
format   encoding     step      bytes
======== ============ ========= =============================================================
gray     ``mono8``    W         luma (OpenCV ``COLOR_BGR2GRAY``)
rgb      ``rgb8``     3 W       R, G, B per pixel
yuv24    ``yuv24``    3 W       Y, U, V per pixel (4:4:4)
yuv422   ``yuv422``   2 W       U Y0 V Y1 per pixel pair (UYVY, the order ROS's ``yuv422``
                                names; ``COLOR_BGR2YUV_UYVY``); the width must be even
======== ============ ========= =============================================================

Both YUV formats use one convention, the one of OpenCV's UYVY conversion (BT.601, video range
16-235 as cameras send it; OpenCV's ``COLOR_BGR2YUV`` is another, full-range one): yuv24 is
OpenCV's UYVY of the image with every pixel doubled, so each pair's chroma is one pixel's.

:func:`decode` goes back to BGR (lossy for gray and yuv422), for viewers and tests.  The byte
layouts themselves are :mod:`wurde_drivers.image_codec`'s (shared with the Eye, which works in RGB);
this module is the VisionModule's BGR face of it.
"""

from __future__ import annotations

import dataclasses
from typing import cast

import cv2
import numpy as np
from numpy.typing import NDArray

from .. import image_codec

__all__ = ['ENCODINGS', 'FORMATS', 'Encoded', 'decode', 'encode']

#: ImagePublisher format -> ROS encoding name (in the order messages list them).
ENCODINGS = {fmt: image_codec.FORMATS[fmt] for fmt in ('gray', 'rgb', 'yuv24', 'yuv422')}
FORMATS = tuple(ENCODINGS)


@dataclasses.dataclass(frozen=True)
class Encoded:
    """One image in a wire format: ``data`` holds ``height`` rows of ``step`` bytes."""

    width: int
    height: int
    encoding: str
    step: int
    data: bytes


def encode(image: NDArray[np.uint8], fmt: str) -> Encoded:
    """``image`` (BGR, or already one channel) in format ``fmt`` (gray, rgb, yuv24, yuv422).

    :raises ValueError: an unknown format, or yuv422 of an odd width.
    """
    if fmt not in ENCODINGS:
        raise ValueError(f'unknown image format "{fmt}"; formats: {", ".join(FORMATS)}')
    rgb = cv2.cvtColor(image, cv2.COLOR_GRAY2RGB if image.ndim == 2 else cv2.COLOR_BGR2RGB)
    height, width = rgb.shape[:2]
    encoding = ENCODINGS[fmt]
    return Encoded(width, height, encoding, width * image_codec.BYTES_PER_PIXEL[encoding],
                   image_codec.encode(rgb, encoding))


def decode(data: bytes | bytearray | memoryview, width: int, height: int, encoding: str,
           step: int | None = None) -> NDArray[np.uint8]:
    """A BGR image from wire bytes (the inverse of :func:`encode`, plus ``bgr8``).

    :raises ValueError: an unknown encoding or too few bytes for the size.
    """
    if encoding == 'bgr8':
        return cast(NDArray[np.uint8], cv2.cvtColor(
            image_codec.decode(width, height, 'rgb8', step or 3 * width, data), cv2.COLOR_RGB2BGR))
    if encoding not in image_codec.BYTES_PER_PIXEL:
        raise ValueError(f'unknown encoding "{encoding}"')
    step = step or width * image_codec.BYTES_PER_PIXEL[encoding]
    return cast(NDArray[np.uint8],
                cv2.cvtColor(image_codec.decode(width, height, encoding, step, data), cv2.COLOR_RGB2BGR))
