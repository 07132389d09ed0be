"""The four ImageTransport encodings to and from RGB: pure functions over bytes (numpy, no ROS).

ImageTransport (see its interface) carries the ImagePublisher's formats (WURDE guide 7.2.3:
gray, rgb, yuv24, yuv422) under ROS image encoding names. The byte layouts, stated once here:

========== ======== ============ ==============================================================
encoding   format   bytes/pixel  layout of one row
========== ======== ============ ==============================================================
``mono8``  gray     1            Y Y Y ...
``rgb8``   rgb      3            R G B R G B ...
``yuv422`` yuv422   2            U0 Y0 V0 Y1 (UYVY, as ROS's ``yuv422`` and IIDC cameras); the
                                 width is even, each pair of pixels shares U and V
``yuv24``  yuv24    3            U Y V U Y V ... (IIDC's YUV 4:4:4 order: 8-bit YUV, no
                                 subsampling)
========== ======== ============ ==============================================================

YUV is full-range BT.601 (JFIF; what IIDC cameras send and libdc1394 converts):
R = Y + 1.402 V', G = Y - 0.344136 U' - 0.714136 V', B = Y + 1.772 U' with U' = U - 128,
V' = V - 128. A row may be padded: ``step`` is its length in bytes, at least width times the
bytes per pixel. Anything else raises :class:`ImageFormatError`.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .errors import CodecError

__all__ = ['BYTES_PER_PIXEL', 'ENCODINGS', 'FORMATS', 'ImageFormatError', 'decode', 'encode',
           'rgb_to_yuv', 'yuv_to_rgb']

#: Bytes per pixel of each encoding.
BYTES_PER_PIXEL = {'mono8': 1, 'rgb8': 3, 'yuv422': 2, 'yuv24': 3}
ENCODINGS = tuple(BYTES_PER_PIXEL)
#: The ImagePublisher's format names (the info's ``format``) -> encodings.
FORMATS = {'gray': 'mono8', 'rgb': 'rgb8', 'yuv422': 'yuv422', 'yuv24': 'yuv24'}

Rgb = npt.NDArray[np.uint8]

_KR, _KB = 0.299, 0.114          # BT.601 luma weights
_KG = 1.0 - _KR - _KB


class ImageFormatError(CodecError):
    """An image whose encoding, size, step or byte count does not hold together."""


def yuv_to_rgb(y: npt.ArrayLike, u: npt.ArrayLike, v: npt.ArrayLike) -> Rgb:
    """Full-range BT.601 YUV planes (same shape, 0..255) -> RGB, shape + (3,), uint8."""
    yf = np.asarray(y, dtype=np.float32)
    uf = np.asarray(u, dtype=np.float32) - 128.0
    vf = np.asarray(v, dtype=np.float32) - 128.0
    r = yf + 2.0 * (1.0 - _KR) * vf
    g = yf - (2.0 * _KB * (1.0 - _KB) / _KG) * uf - (2.0 * _KR * (1.0 - _KR) / _KG) * vf
    b = yf + 2.0 * (1.0 - _KB) * uf
    return np.clip(np.rint(np.stack((r, g, b), axis=-1)), 0, 255).astype(np.uint8)


def rgb_to_yuv(rgb: npt.ArrayLike) -> npt.NDArray[np.uint8]:
    """RGB (..., 3) -> full-range BT.601 YUV (..., 3) as Y, U, V, uint8."""
    f = np.asarray(rgb, dtype=np.float32)
    y = _KR * f[..., 0] + _KG * f[..., 1] + _KB * f[..., 2]
    u = (f[..., 2] - y) / (2.0 * (1.0 - _KB)) + 128.0
    v = (f[..., 0] - y) / (2.0 * (1.0 - _KR)) + 128.0
    return np.clip(np.rint(np.stack((y, u, v), axis=-1)), 0, 255).astype(np.uint8)


def _rows(width: int, height: int, encoding: str, step: int, data: bytes | memoryview | np.ndarray
          ) -> npt.NDArray[np.uint8]:
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
    return buffer[:step * height].reshape(height, step)[:, :row]


def decode(width: int, height: int, encoding: str, step: int,
           data: bytes | memoryview | np.ndarray) -> Rgb:
    """One ImageTransport image -> RGB pixels, shape (height, width, 3), uint8.

    :raises ImageFormatError: for an unknown encoding or sizes that do not fit the bytes.
    """
    rows = _rows(width, height, encoding, step, data)
    if encoding == 'mono8':
        return np.repeat(rows[:, :, None], 3, axis=2)
    if encoding == 'rgb8':
        return rows.reshape(height, width, 3).copy()
    if encoding == 'yuv24':
        uyv = rows.reshape(height, width, 3)
        return yuv_to_rgb(uyv[..., 1], uyv[..., 0], uyv[..., 2])
    quads = rows.reshape(height, width // 2, 4)          # U0 Y0 V0 Y1
    y = rows.reshape(height, width, 2)[..., 1]
    u = np.repeat(quads[..., 0], 2, axis=1)
    v = np.repeat(quads[..., 2], 2, axis=1)
    return yuv_to_rgb(y, u, v)


def encode(rgb: npt.ArrayLike, encoding: str) -> bytes:
    """RGB pixels (height, width, 3) -> the bytes of ``encoding`` with no row padding
    (step = width times the bytes per pixel). yuv422 averages U and V over each pixel pair.

    :raises ImageFormatError: for an unknown encoding, a shape that is not (h, w, 3) or an odd
        width in yuv422.
    """
    pixels = np.asarray(rgb)
    if pixels.ndim != 3 or pixels.shape[2] != 3 or 0 in pixels.shape:
        raise ImageFormatError(f'RGB pixels must have shape (height, width, 3), not {pixels.shape}')
    pixels = pixels.astype(np.uint8, copy=False)
    height, width, _ = pixels.shape
    if encoding == 'rgb8':
        return pixels.tobytes()
    if encoding == 'mono8':
        return rgb_to_yuv(pixels)[..., 0].tobytes()
    if encoding == 'yuv24':
        return rgb_to_yuv(pixels)[..., [1, 0, 2]].tobytes()
    if encoding == 'yuv422':
        if width % 2:
            raise ImageFormatError(f'yuv422 needs an even width, not {width}')
        yuv = rgb_to_yuv(pixels).astype(np.uint16)
        pairs = yuv.reshape(height, width // 2, 2, 3)
        quads = np.empty((height, width // 2, 4), dtype=np.uint8)
        quads[..., 0] = (pairs[..., 0, 1] + pairs[..., 1, 1] + 1) // 2
        quads[..., 1] = pairs[..., 0, 0]
        quads[..., 2] = (pairs[..., 0, 2] + pairs[..., 1, 2] + 1) // 2
        quads[..., 3] = pairs[..., 1, 0]
        return quads.tobytes()
    raise ImageFormatError(f'encoding {encoding!r} is none of {", ".join(ENCODINGS)}')
