"""eye on its web page: no X display, the pattern camera publishing yuv24 (8-bit YUV 4:4:4), the
installed ``eye``, and headless Chromium (driven over DevTools, :mod:`cdp`) on the page: the
page's script replaces the frames as they come, its screenshot is compared with the published
frames, and a click and a key press in the page come back in ImageDisplay's data."""

from __future__ import annotations

import pathlib
import re
import socket
import time
from collections.abc import Callable
from typing import Any

from cdp import Browser
from eye_fixture import eye, pattern_camera, status
from pattern_supplier import which_frame
from sim_fixture import Observer

MEAN_TOLERANCE, MAX_TOLERANCE = 1.0, 4.0
FRAME = 'Number(document.body ? document.body.dataset.frame || 0 : 0)'


def page_until(browser: Browser, expression: str, accept: Callable[[Any], bool], what: str,
               timeout: float = 20.0) -> Any:
    """The value of ``expression`` in the page once ``accept`` takes it (asked every 50 ms)."""
    deadline = time.monotonic() + timeout
    while True:
        value = browser.evaluate(expression)
        if accept(value):
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f'{what}: not in the page within {timeout} s ({value!r})')
        time.sleep(0.05)


def test_page_shows_the_published_frames(ros_domain: int, tmp_path: pathlib.Path) -> None:
    observer = Observer({'Eye': 'ImageDisplay'})
    try:
        with pattern_camera('Camera', 'yuv24'), \
                eye(['-i', 'Camera', '-d', 'web', '-p', '0'], display=None) as child, \
                Browser(tmp_path, (320, 280)) as browser:
            line = child.expect('shows Camera on http://', timeout=30)
            url = re.search(r'http://127\.0\.0\.1:\d+/', line)
            assert url, f'not on 127.0.0.1 by default: {line}'
            browser.open(url.group(0))
            # The page's script takes each new frame as it comes (a long poll, no timer).
            first = page_until(browser, FRAME, lambda n: n >= 1, 'a frame')
            page_until(browser, FRAME, lambda n: n >= first + 2, 'two frames more')
            assert browser.evaluate('document.title') == 'Eye: Camera'
            k, mean, largest = which_frame(browser.screenshot())
            assert mean <= MEAN_TOLERANCE and largest <= MAX_TOLERANCE, (k, mean, largest)

            # A click on the image and a key press, as a person would.
            browser.click(100, 50)
            browser.key(65, 'a')
            observer.until(lambda o: (s := status(o)) is not None and s.click_count == 1
                           and s.key == 65, 'the click and the key in the status')
            last = status(observer)
            assert (last.click_x, last.click_y) == (100, 50)
            assert last.frames_shown >= 3 and last.display_rate > 0
            # Hidden: the page hides the image.
            observer.request('Eye', visible=False)
            page_until(browser, "document.getElementById('frame').style.visibility",
                       lambda v: v == 'hidden', 'the image hidden')
            observer.until(lambda o: 'Eye' in o.infos and o.infos['Eye'].visible is False,
                           'visible false in the info')
    finally:
        observer.close()
    assert child.process.returncode == 0, child.stderr[-3000:]

def test_a_display_that_cannot_open_ends_the_eye_or_gives_way(ros_domain: int) -> None:
    """A taken port or ``-d window`` without a display: exit status 2 and why; ``auto`` with a
    DISPLAY that no X server answers falls back to the page."""
    with socket.socket() as taken:
        taken.bind(('127.0.0.1', 0))
        taken.listen()
        port = taken.getsockname()[1]
        with eye(['-i', 'Camera', '-d', 'web', '-p', str(port)], display=None) as busy, \
                eye(['-i', 'Camera', '-d', 'window'], display=None) as windowless, \
                eye(['-i', 'Camera', '-p', '0'], display=':987') as fallback:
            fallback.expect('shows Camera on http://127.0.0.1:', timeout=30)
            assert busy.process.wait(timeout=30) == 2
            assert windowless.process.wait(timeout=30) == 2
    assert f'eye: cannot serve on 127.0.0.1:{port}' in busy.stderr, busy.stderr
    assert 'eye: no window on display None' in windowless.stderr, windowless.stderr
    assert "no window on display ':987'" in fallback.stderr
    assert 'showing the web page instead' in fallback.stderr
    assert fallback.process.returncode == 0, fallback.stderr[-3000:]
