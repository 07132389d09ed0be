"""The Eye's frame store and display status, without ROS or a screen: composition, waiting for a
newer frame across threads, PNG once per frame, each frame counted once."""

from __future__ import annotations

import threading
import time

import cv2
import numpy as np
from pattern_supplier import pattern

from wurde_drivers.eye.frames import DisplaySettings, FrameStore, compose, ppm
from wurde_drivers.eye.status import DisplayStatus


def test_compose_scales_by_whole_pixels_and_overlays() -> None:
    rgb = pattern(1, 64, 48)
    doubled = compose(rgb, DisplaySettings(scale=2.0))
    assert doubled.shape == (96, 128, 3) and (doubled[::2, ::2] == rgb).all()
    marked = compose(rgb, DisplaySettings(overlay='x'))
    assert marked.shape == rgb.shape and (marked[:4, :4] < rgb[:4, :4]).any()
    assert (marked[30:] == rgb[30:]).all() and (rgb == pattern(1, 64, 48)).all()   # not in place
    assert ppm(rgb[:1, :2]) == b'P6\n2 1\n255\n' + rgb[:1, :2].tobytes()


def test_a_reader_waits_for_the_next_frame_and_the_png_is_made_once() -> None:
    store = FrameStore(DisplaySettings())
    assert store.latest() is None and store.wait_newer(0, 0.01) is None
    got = []
    reader = threading.Thread(target=lambda: got.append(store.wait_newer(0, 10.0)))
    reader.start()
    first = store.put(pattern(2), 2)
    reader.join(10.0)
    assert got == [first] and (first.index, first.source_index) == (1, 2)
    png = store.png(first)
    assert store.png(first) is png                                  # cached for every client
    shown = cv2.cvtColor(cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR),
                         cv2.COLOR_BGR2RGB)
    assert (shown == pattern(2)).all()                             # lossless
    again = store.set_settings(DisplaySettings(scale=0.5))         # the last image recomposed
    assert again is not None and again.index == 2 and again.rgb.shape == (120, 160, 3)
    assert not again.rgb.flags.writeable
    store.close()
    start = time.monotonic()
    assert store.wait_newer(2, 10.0) is None and time.monotonic() - start < 5.0   # woken


def test_status_counts_each_frame_once_and_keeps_the_last_click_and_key() -> None:
    status = DisplayStatus()
    assert status.shown(1) and not status.shown(1) and status.shown(3) and not status.shown(2)
    status.click(10, 20)
    status.click(5, 6)
    status.key(97)
    snapshot = status.snapshot()
    assert (snapshot.frames_shown, snapshot.click_count, snapshot.click_x, snapshot.click_y,
            snapshot.key) == (2, 2, 5, 6, 97)
    assert snapshot.display_rate == 1.0                            # two frames in the last 2 s
