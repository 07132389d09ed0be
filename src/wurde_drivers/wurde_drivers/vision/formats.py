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

:func:`decode` goes back to BGR (lossy for gray and yuv422), for viewers and tests.
"""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ['ENCODINGS', 'FORMATS', 'Encoded', 'decode', 'encode']

#: ImagePublisher format -> ROS encoding name.
ENCODINGS = {'gray': 'mono8', 'rgb': 'rgb8', 'yuv24': 'yuv24', 'yuv422': 'yuv422'}
FORMATS = tuple(ENCODINGS)
_CHANNELS = {'mono8': 1, 'rgb8': 3, 'yuv24': 3, 'yuv422': 2}


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
    if image.ndim == 2:
        image = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    height, width = image.shape[:2]
    if fmt == 'gray':
        out = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    elif fmt == 'rgb':
        out = cv2.cvtColor(image, cv2.COLOR_BGR2RGB)
    elif fmt == 'yuv24':
        pairs = cv2.cvtColor(np.repeat(image, 2, axis=1), cv2.COLOR_BGR2YUV_UYVY)
        out = pairs.reshape(height, width, 4)[:, :, (1, 0, 2)]      # U Y V Y -> Y U V
    else:
        if width % 2:
            raise ValueError(f'yuv422 needs an even width, not {width}')
        out = cv2.cvtColor(image, cv2.COLOR_BGR2YUV_UYVY)
    encoding = ENCODINGS[fmt]
    return Encoded(width, height, encoding, width * _CHANNELS[encoding], out.tobytes())


def decode(data: bytes | bytearray | memoryview, width: int, height: int, encoding: str,
           step: int | None = None) -> NDArray[np.uint8]:
    """A BGR image from wire bytes (the inverse of :func:`encode`, plus ``bgr8``).

    :raises ValueError: an unknown encoding or too few bytes for the size.
    """
    channels = {**_CHANNELS, 'bgr8': 3}.get(encoding)
    if channels is None:
        raise ValueError(f'unknown encoding "{encoding}"')
    row = width * channels
    step = step or row
    if step < row or len(data) < step * height:
        raise ValueError(f'{len(data)} bytes (step {step}) are too few for {width}x{height} {encoding}')
    rows = np.frombuffer(data, np.uint8, step * height).reshape(height, step)[:, :row]
    pixels = np.ascontiguousarray(rows).reshape(height, width, channels)
    if encoding == 'mono8':
        return cv2.cvtColor(pixels, cv2.COLOR_GRAY2BGR)
    if encoding == 'rgb8':
        return cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR)
    if encoding == 'yuv24':
        uyvy = pixels[:, :, (1, 0, 2, 0)].reshape(height, width * 2, 2)
        return np.ascontiguousarray(cv2.cvtColor(uyvy, cv2.COLOR_YUV2BGR_UYVY)[:, ::2])
    if encoding == 'yuv422':
        return cv2.cvtColor(pixels, cv2.COLOR_YUV2BGR_UYVY)
    return pixels.copy()
