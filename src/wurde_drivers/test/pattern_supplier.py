"""A test camera: an ImageTransport supplier (wurde_core's ImageSource) of a known pattern.

Run as a program (``python pattern_supplier.py -i STREAM -e ENCODING -W 320 -H 240 -f 10``)
it publishes :func:`pattern` ``(k)`` as frame ``k`` = 1, 2, ... in the given encoding; the
tests import :func:`pattern` and :func:`which_frame` to tell which frame a screenshot shows.
"""

from __future__ import annotations

import sys

import numpy as np

#: 75 % colour bars: inside the YUV gamut, so every encoding carries them within rounding.
BARS = np.array([(191, 191, 191), (191, 191, 0), (0, 191, 191), (0, 191, 0), (191, 0, 191),
                 (191, 0, 0), (0, 0, 191), (16, 16, 16)], dtype=np.uint8)
#: Frames differ in the place of a white square, one of this many.
PLACES = 8


def pattern(k: int, width: int = 320, height: int = 240) -> np.ndarray:
    """Frame ``k``: eight vertical colour bars over the top three quarters, grey steps of 16 px
    below, and a white 16x16 square at one of :data:`PLACES` places along the top (by ``k``).
    Every edge falls on an even column, so yuv422's shared chroma smears nothing."""
    rgb = np.empty((height, width, 3), dtype=np.uint8)
    columns = np.arange(width)
    rgb[:, :] = BARS[np.minimum(columns * len(BARS) // width, len(BARS) - 1)]
    steps = height * 3 // 4
    rgb[steps:, :] = ((columns // 16 * 16 * 255) // max(1, width - 1)).astype(np.uint8)[:, None]
    x = 8 + (width - 32) * (k % PLACES) // PLACES // 2 * 2
    rgb[8:24, x:x + 16] = 255
    return rgb


def which_frame(image: np.ndarray, width: int = 320, height: int = 240) -> tuple[int, float, float]:
    """``(k % PLACES, mean error, max error)`` of the pattern that ``image`` (RGB, at least
    width x height, the picture at its top-left) is closest to."""
    shot = image[:height, :width, :3].astype(int)
    errors = [np.abs(shot - pattern(k, width, height)) for k in range(PLACES)]
    best = int(np.argmin([e.mean() for e in errors]))
    return best, float(errors[best].mean()), float(errors[best].max())


def main(argv: list[str]) -> int:
    from wurde_core import CommsManager, RunState
    from wurde_core.interfaces import ImageSource

    from wurde_drivers.image_codec import encode

    manager = CommsManager('PatternCamera')
    opts = manager.parse_options(argv, 'i:e:W:H:f:')
    width, height = int(opts.user.get('W', '320')), int(opts.user.get('H', '240'))
    encoding, rate = opts.user.get('e', 'rgb8'), float(opts.user.get('f', '10'))
    camera = ImageSource(opts.user.get('i', 'Camera'))
    manager.register_supplier(camera)
    manager.set_sleep(1.0 / rate)
    info = camera.info
    info.camera.set_value('pattern')
    info.format.set_value({'mono8': 'gray', 'rgb8': 'rgb'}.get(encoding, encoding))
    info.width.set_value(width)
    info.height.set_value(height)
    info.frame_rate.set_value(rate)
    camera.publish_info()
    frames = [encode(pattern(k, width, height), encoding) for k in range(PLACES)]
    k = 0
    while manager.run_update() == RunState.RUN:
        k += 1
        camera.publish_image(width, height, encoding, frames[k % PLACES], frame_index=k)
    manager.clean_up()
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
