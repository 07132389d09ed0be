"""The four ImageTransport encodings to and from RGB: pure functions over bytes (numpy and
OpenCV's colour conversions, no ROS).

ImageTransport (see its interface) carries the ImagePublisher's formats (WURDE guide 7.2.3:
gray, rgb, yuv24, yuv422) under ROS image encoding names. The byte layouts, stated once here:

========== ======== ============ ==============================================================
encoding   format   bytes/pixel  layout of one row
========== ======== ============ ==============================================================
``mono8``  gray     1            Y Y Y ... (luma 0.299 R + 0.587 G + 0.114 B, full range)
``rgb8``   rgb      3            R G B R G B ...
``yuv422`` yuv422   2            U0 Y0 V0 Y1 per pixel pair (UYVY, the order ROS's ``yuv422``
                                 names); the width is even
``yuv24``  yuv24    3            Y U V Y U V ... (8-bit YUV 4:4:4: no chroma subsampling)
========== ======== ============ ==============================================================

Both YUV encodings follow one convention, OpenCV's UYVY conversion (BT.601, video range: Y in
16-235, U and V in 16-240, as cameras send it), the one the VisionModule's ImagePublisher uses;
yuv24 is that conversion of the image with every pixel doubled, so each pixel keeps its own
chroma. A row may be padded: ``step`` is its length in bytes, at least width times the bytes
per pixel. Anything else raises :class:`ImageFormatError`.
"""

from __future__ import annotations

from typing import cast

import cv2
import numpy as np
import numpy.typing as npt

from .errors import CodecError

__all__ = ['BYTES_PER_PIXEL', 'ENCODINGS', 'FORMATS', 'ImageFormatError', 'decode', 'encode']

#: Bytes per pixel of each encoding.
BYTES_PER_PIXEL = {'mono8': 1, 'rgb8': 3, 'yuv422': 2, 'yuv24': 3}
ENCODINGS = tuple(BYTES_PER_PIXEL)
#: The ImagePublisher's format names (the info's ``format``) -> encodings.
FORMATS = {'gray': 'mono8', 'rgb': 'rgb8', 'yuv422': 'yuv422', 'yuv24': 'yuv24'}

Rgb = npt.NDArray[np.uint8]


class ImageFormatError(CodecError):
    """An image whose encoding, size, step or byte count does not hold together."""


def _rows(width: int, height: int, encoding: str, step: int,
          data: bytes | bytearray | memoryview | np.ndarray) -> npt.NDArray[np.uint8]:
    """The pixel bytes as (height, width * bytes per pixel), padding cut off; checks everything."""
    if encoding not in BYTES_PER_PIXEL:
        raise ImageFormatError(f'encoding {encoding!r} is none of {", ".join(ENCODINGS)}')
    if width <= 0 or height <= 0:
        raise ImageFormatError(f'image size {width}x{height} is not positive')
    if encoding == 'yuv422' and width % 2:
        raise ImageFormatError(f'yuv422 needs an even width, not {width}')
    row = width * BYTES_PER_PIXEL[encoding]
    if step < row:
        raise ImageFormatError(f'step {step} is shorter than a {encoding} row of {width} pixels '
                               f'({row} bytes)')
    buffer = np.frombuffer(data, dtype=np.uint8) if not isinstance(data, np.ndarray) \
        else data.reshape(-1).view(np.uint8)
    if buffer.size < step * height:
        raise ImageFormatError(f'{buffer.size} bytes for {height} rows of {step}: '
                               f'{step * height} needed')
    return np.ascontiguousarray(buffer[:step * height].reshape(height, step)[:, :row])


def decode(width: int, height: int, encoding: str, step: int,
           data: bytes | bytearray | memoryview | np.ndarray) -> Rgb:
    """One ImageTransport image -> RGB pixels, shape (height, width, 3), uint8.

    :raises ImageFormatError: for an unknown encoding or sizes that do not fit the bytes.
    """
    rows = _rows(width, height, encoding, step, data)
    if encoding == 'mono8':
        return np.repeat(rows[:, :, None], 3, axis=2)
    if encoding == 'rgb8':
        return rows.reshape(height, width, 3).copy()          # never a view of the message
    if encoding == 'yuv422':
        return cast(Rgb, cv2.cvtColor(rows.reshape(height, width, 2), cv2.COLOR_YUV2RGB_UYVY))
    yuv = rows.reshape(height, width, 3)                      # yuv24: each pixel a UYVY pair
    uyvy = np.ascontiguousarray(yuv[:, :, (1, 0, 2, 0)]).reshape(height, width * 2, 2)
    return np.ascontiguousarray(cv2.cvtColor(uyvy, cv2.COLOR_YUV2RGB_UYVY)[:, ::2])


def encode(rgb: npt.ArrayLike, encoding: str) -> bytes:
    """RGB pixels (height, width, 3) -> the bytes of ``encoding`` with no row padding
    (step = width times the bytes per pixel).

    :raises ImageFormatError: for an unknown encoding, a shape that is not (h, w, 3) or an odd
        width in yuv422.
    """
    pixels = np.asarray(rgb)
    if pixels.ndim != 3 or pixels.shape[2] != 3 or 0 in pixels.shape:
        raise ImageFormatError(f'RGB pixels must have shape (height, width, 3), not {pixels.shape}')
    pixels = np.ascontiguousarray(pixels, dtype=np.uint8)
    height, width, _ = pixels.shape
    if encoding == 'rgb8':
        return pixels.tobytes()
    if encoding == 'mono8':
        return cv2.cvtColor(pixels, cv2.COLOR_RGB2GRAY).tobytes()
    if encoding == 'yuv422':
        if width % 2:
            raise ImageFormatError(f'yuv422 needs an even width, not {width}')
        return cv2.cvtColor(pixels, cv2.COLOR_RGB2YUV_UYVY).tobytes()
    if encoding == 'yuv24':
        pairs = cv2.cvtColor(np.repeat(pixels, 2, axis=1), cv2.COLOR_RGB2YUV_UYVY)
        return np.ascontiguousarray(pairs.reshape(height, width, 4)[:, :, (1, 0, 2)]).tobytes()
    raise ImageFormatError(f'encoding {encoding!r} is none of {", ".join(ENCODINGS)}')
