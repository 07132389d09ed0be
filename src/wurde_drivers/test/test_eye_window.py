"""eye in a window: a real Xvfb display, the pattern camera publishing yuv422, the installed
``eye``; the screen itself (Xvfb's framebuffer file) is compared with the published frames."""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable

import numpy as np
import pytest
from eye_fixture import eye, pattern_camera, status
from pattern_supplier import PLACES, pattern, which_frame
from screens import read_xwd, xvfb
from sim_fixture import Observer
from wurde_core import LockedError
from xinput import FakeInput

#: yuv422 carries the pattern within rounding (its edges fall on pixel pairs).
MEAN_TOLERANCE, MAX_TOLERANCE = 1.0, 4.0


def screen_until(framebuffer: pathlib.Path, accept: Callable[[np.ndarray], bool], what: str,
                 timeout: float = 20.0) -> np.ndarray:
    """The screen once ``accept(screen)`` holds; the framebuffer is read every 50 ms until then."""
    deadline = time.monotonic() + timeout
    while True:
        screen = read_xwd(framebuffer)
        if accept(screen):
            return screen
        if time.monotonic() > deadline:
            raise AssertionError(f'{what}: not on the screen within {timeout} s '
                                 f'(closest frame {which_frame(screen)})')
        time.sleep(0.05)


def test_window_shows_the_published_frames(ros_domain: int, tmp_path: pathlib.Path) -> None:
    observer = Observer({'Eye': 'ImageDisplay'})
    try:
        with xvfb(tmp_path) as (display, framebuffer), pattern_camera('Camera', 'yuv422'), \
                eye(['-i', 'Camera', '-d', 'window'], display=display) as child:
            child.expect('shows Camera in a window', timeout=30)
            observer.until(lambda o: (s := status(o)) is not None and s.frames_shown >= 2
                           and 'Eye' in o.infos, 'two frames shown, and the info', timeout=30)
            info = observer.infos['Eye']
            assert (info.stream, info.visible, info.scale, info.title) == ('Camera', True, 1.0,
                                                                          'Eye: Camera')
            # What is on the screen is a published frame, pixel for pixel within yuv422's rounding.
            def published(screen: np.ndarray) -> bool:
                _, mean, largest = which_frame(screen)
                return mean <= MEAN_TOLERANCE and largest <= MAX_TOLERANCE
            first = which_frame(screen_until(framebuffer, published, 'a published frame'))[0]
            # ... and the window follows the camera: another frame comes on the screen.
            screen_until(framebuffer, lambda s: published(s) and which_frame(s)[0] != first,
                         'a later frame')
            observer.until(lambda o: status(o).display_rate > 1.0, 'the display rate')
            # A person clicks into the image and presses 'a' (X keysym 0x61).
            person = FakeInput(display)
            person.click(100, 50)
            person.key(0x61)
            observer.until(lambda o: status(o).click_count == 1 and status(o).key == 0x61,
                           'the click and the key in the status')
            assert (status(observer).click_x, status(observer).click_y) == (100, 50)

            # Requests: scale 2 with an overlay; the stream is the Eye's to choose (locked).
            with pytest.raises(LockedError):
                observer.obj('Eye').requests.stream.set_value('Other')
            observer.request('Eye', scale=0.0)                        # refused: not > 0
            observer.request('Eye', scale=2.0, overlay='left camera', title='Left')
            observer.until(lambda o: o.infos['Eye'].scale == 2.0, 'scale 2 in the info')
            assert (observer.infos['Eye'].overlay, observer.infos['Eye'].title) == ('left camera',
                                                                                  'Left')

            def doubled(screen: np.ndarray) -> bool:
                """A 640x480 window (nothing beside or below it) of a frame at twice its size;
                the overlay's band (top 30 rows) aside."""
                if screen[:, 640:].max() or screen[480:, :].max():
                    return False
                half = screen[30:480:2, :640:2].astype(int)
                return any(np.abs(half - pattern(k)[15:]).max() <= MAX_TOLERANCE
                           for k in range(PLACES))
            screen = screen_until(framebuffer, doubled, 'the frame at twice its size')
            # The overlay darkens a band in the top-left corner and writes white text in it.
            band = screen[:20, :100].astype(int)
            assert band.max() >= 200 and np.median(band) < 100
            # A click at twice the place is the same image pixel.
            person.click(200, 100)
            observer.until(lambda o: status(o).click_count == 2, 'the second click')
            assert (status(observer).click_x, status(observer).click_y) == (100, 50)
            # Closing the window ends the Eye, cleanly.
            assert person.close_windows() >= 1
            assert child.process.wait(timeout=20) == 0, child.stderr[-3000:]
            person.close()
    finally:
        observer.close()
    assert child.process.returncode == 0, child.stderr[-3000:]

