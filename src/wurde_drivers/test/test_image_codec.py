"""The ImageTransport encodings (wurde_drivers.image_codec): known values, round trips, padded
rows and refusals. Pure numpy, no ROS."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from wurde_drivers.image_codec import BYTES_PER_PIXEL, ENCODINGS, ImageFormatError, decode, encode

#: BT.601 video range of pure colours, (R, G, B) -> (Y, U, V): Y = 16 + 219 * luma / 255,
#: U and V = 128 + 224 * (B - luma) / 1.772 / 255 and 128 + 224 * (R - luma) / 1.402 / 255.
KNOWN = {(255, 0, 0): (82, 90, 240), (0, 255, 0): (145, 54, 34), (0, 0, 255): (41, 240, 110),
         (255, 255, 255): (235, 128, 128), (0, 0, 0): (16, 128, 128),
         (128, 128, 128): (126, 128, 128)}


@pytest.mark.parametrize('rgb, yuv', KNOWN.items())
def test_known_colours(rgb: tuple[int, int, int], yuv: tuple[int, int, int]) -> None:
    pixel = np.array([[rgb]], dtype=np.uint8)
    assert tuple(encode(pixel, 'yuv24')) == yuv
    assert tuple(encode(np.repeat(pixel, 2, axis=1), 'yuv422')) == (yuv[1], yuv[0], yuv[2], yuv[0])
    back = decode(1, 1, 'yuv24', 3, bytes(yuv))
    assert np.abs(back.astype(int) - rgb).max() <= 1


def test_layouts_byte_by_byte() -> None:
    """Two pixels, red then blue: each encoding's bytes as its table says."""
    rgb = np.array([[[255, 0, 0], [0, 0, 255]]], dtype=np.uint8)
    assert encode(rgb, 'rgb8') == bytes([255, 0, 0, 0, 0, 255])
    assert encode(rgb, 'mono8') == bytes([76, 29])
    assert encode(rgb, 'yuv24') == bytes([82, 90, 240, 41, 240, 110])       # Y U V
    assert encode(rgb, 'yuv422') == bytes([165, 82, 175, 41])               # U Y0 V Y1, shared
    gray = decode(2, 1, 'mono8', 2, bytes([10, 200]))
    assert gray.tolist() == [[[10, 10, 10], [200, 200, 200]]]


@settings(max_examples=40, deadline=None)
@given(arrays(np.uint8, st.tuples(st.integers(1, 6), st.integers(1, 4).map(lambda n: 2 * n),
                                  st.just(3))),
       st.sampled_from(ENCODINGS), st.integers(0, 5))
def test_round_trip_with_padding(rgb: np.ndarray, encoding: str, padding: int) -> None:
    """encode then decode (rows padded by ``padding`` bytes) gives the picture back: exactly for
    rgb8, as luma for mono8, within 8-bit video-range rounding for yuv24 and for yuv422 (on pixel
    pairs of one colour: the pair shares its chroma)."""
    if encoding == 'yuv422':
        rgb = np.repeat(rgb[:, ::2], 2, axis=1)          # pairs of one colour: nothing to share
    height, width, _ = rgb.shape
    row = width * BYTES_PER_PIXEL[encoding]
    packed = np.frombuffer(encode(rgb, encoding), dtype=np.uint8).reshape(height, row)
    padded = np.concatenate([packed, np.full((height, padding), 77, np.uint8)], axis=1)
    back = decode(width, height, encoding, row + padding, padded.tobytes()).astype(int)
    assert back.shape == rgb.shape
    if encoding == 'rgb8':
        assert (back == rgb).all()
    elif encoding == 'mono8':
        luma = np.rint(rgb.astype(float) @ [0.299, 0.587, 0.114])
        assert np.abs(back - luma[..., None]).max() <= 1 and (back == back[..., :1]).all()
    else:
        assert np.abs(back - rgb).max() <= 2


@pytest.mark.parametrize('args, message', [
    ((4, 2, 'bgr8', 12, bytes(24)), 'none of'),
    ((0, 2, 'rgb8', 0, b''), 'not positive'),
    ((3, 2, 'yuv422', 6, bytes(12)), 'even width'),
    ((4, 2, 'rgb8', 11, bytes(24)), 'shorter than'),
    ((4, 2, 'rgb8', 12, bytes(23)), '24 needed'),
])
def test_refusals_say_why(args: tuple, message: str) -> None:
    with pytest.raises(ImageFormatError, match=message):
        decode(*args)
    assert issubclass(ImageFormatError, ValueError)


def test_encode_refuses_what_it_cannot_write() -> None:
    with pytest.raises(ImageFormatError, match='shape'):
        encode(np.zeros((2, 2), np.uint8), 'rgb8')
    with pytest.raises(ImageFormatError, match='even width'):
        encode(np.zeros((2, 3, 3), np.uint8), 'yuv422')
    with pytest.raises(ImageFormatError, match='none of'):
        encode(np.zeros((2, 2, 3), np.uint8), 'jpeg')
