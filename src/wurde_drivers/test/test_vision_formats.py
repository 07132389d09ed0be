"""The ImagePublisher's formats (guide 7.2.3) against OpenCV's own conversions, byte for byte."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from wurde_drivers.vision.formats import decode, encode

IMAGE = np.random.default_rng(7).integers(0, 256, (48, 64, 3), dtype=np.uint8)   # BGR


def test_gray_is_opencv_luma() -> None:
    out = encode(IMAGE, 'gray')
    assert (out.encoding, out.step, out.width, out.height) == ('mono8', 64, 64, 48)
    assert out.data == cv2.cvtColor(IMAGE, cv2.COLOR_BGR2GRAY).tobytes()


def test_rgb_swaps_the_channels() -> None:
    out = encode(IMAGE, 'rgb')
    assert (out.encoding, out.step) == ('rgb8', 192)
    pixels = np.frombuffer(out.data, np.uint8).reshape(48, 64, 3)
    assert np.array_equal(pixels, IMAGE[:, :, ::-1])
    assert np.array_equal(decode(out.data, 64, 48, 'rgb8'), IMAGE)


def test_yuv24_is_opencv_uyvy_at_full_chroma_resolution() -> None:
    out = encode(IMAGE, 'yuv24')
    assert (out.encoding, out.step) == ('yuv24', 192)
    yuv = np.frombuffer(out.data, np.uint8).reshape(48, 64, 3)
    # Each pixel as a pair of itself through OpenCV's UYVY conversion: U Y V Y.
    for row, col in ((0, 0), (10, 33), (47, 63)):
        pair = np.repeat(IMAGE[row:row + 1, col:col + 1], 2, axis=1)
        u, y, v, y1 = cv2.cvtColor(pair, cv2.COLOR_BGR2YUV_UYVY).reshape(4)
        assert tuple(yuv[row, col]) == (y, u, v) and y1 == y
    # The luma is yuv422's, pixel for pixel (one convention for both).
    luma422 = np.frombuffer(encode(IMAGE, 'yuv422').data, np.uint8).reshape(48, 64, 2)[:, :, 1]
    assert np.array_equal(yuv[:, :, 0], luma422)
    back = decode(out.data, 64, 48, 'yuv24')
    assert np.abs(back.astype(int) - IMAGE).max() <= 3       # video range: a little rounding


def test_yuv422_is_uyvy() -> None:
    out = encode(IMAGE, 'yuv422')
    assert (out.encoding, out.step) == ('yuv422', 128)
    assert out.data == cv2.cvtColor(IMAGE, cv2.COLOR_BGR2YUV_UYVY).tobytes()
    # UYVY: every odd byte is a pixel's luma, BT.601 video range (16 + 219 * Y').
    luma = np.frombuffer(out.data, np.uint8).reshape(48, 64, 2)[:, :, 1]
    b, g, r = (IMAGE[:, :, i].astype(float) for i in range(3))
    expected = 16 + (0.299 * r + 0.587 * g + 0.114 * b) * 219 / 255
    assert np.abs(luma - expected).max() <= 1
    flat = np.full((4, 4, 3), (40, 200, 90), np.uint8)     # a flat colour survives 4:2:2
    back = decode(encode(flat, 'yuv422').data, 4, 4, 'yuv422')
    assert np.abs(back.astype(int) - flat).max() <= 2


def test_bad_formats_and_sizes_are_refused() -> None:
    with pytest.raises(ValueError, match='unknown image format "bgr"'):
        encode(IMAGE, 'bgr')
    with pytest.raises(ValueError, match='even width'):
        encode(IMAGE[:, :63], 'yuv422')
    with pytest.raises(ValueError, match='3072 needed'):
        decode(b'\0' * 10, 64, 48, 'mono8')
    assert encode(IMAGE[:, :, 0], 'gray').data == IMAGE[:, :, 0].tobytes()   # one channel in
