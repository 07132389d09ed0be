"""The ImageSource wrapper of ImageTransport: an image travels whole, its bytes handed over as
they are (the Eye reads them with ``pixels()``)."""

from __future__ import annotations

from conftest import until
from wurde_core import CommsManager
from wurde_core.interfaces import ImageSource


def test_an_image_travels_whole(manager: CommsManager) -> None:
    camera = ImageSource('Camera')
    manager.register_supplier(camera)
    eye = ImageSource('Camera')
    eye.set_queue_mode(True)
    manager.register_consumer(eye)
    until(manager, lambda: eye.peers() > 0, what='match')
    pixels = bytes(range(256)) * 900                          # 320 x 240 rgb8
    assert camera.publish_image(320, 240, 'rgb8', pixels)
    assert (camera.data.step, camera.data.frame_index) == (960, 1)     # defaults: packed, counted
    padded = bytes(1000 * 2)                                  # two mono8 rows of 999 + 1 padding
    assert camera.publish_image(999, 2, 'mono8', padded, step=1000, frame_index=7)
    got = []

    def collect() -> bool:
        while eye.get_next_data():
            d = eye.data
            got.append((d.width, d.height, d.encoding, d.step, d.frame_index, eye.pixels().tobytes()))
        return len(got) == 2

    until(manager, collect, what='two images')
    assert got[0] == (320, 240, 'rgb8', 960, 1, pixels)
    assert got[1] == (999, 2, 'mono8', 1000, 7, padded)
