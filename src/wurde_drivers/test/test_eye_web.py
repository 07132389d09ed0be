"""eye on its web page: no X display, the pattern camera publishing yuv24 (8-bit YUV 4:4:4), the
installed ``eye``; headless Chromium's screenshot of the page is compared with the published
frames, and clicks and keys sent as the page sends them come back in ImageDisplay's data."""

from __future__ import annotations

import pathlib
import re
import socket
import urllib.request

from eye_fixture import eye, pattern_camera, status
from pattern_supplier import which_frame
from screens import chromium_screenshot
from sim_fixture import Observer

MEAN_TOLERANCE, MAX_TOLERANCE = 1.0, 4.0


def fetch(url: str, *, method: str = 'GET', timeout: float = 10.0) -> tuple[int, dict[str, str], bytes]:
    request = urllib.request.Request(url, method=method)
    with urllib.request.urlopen(request, timeout=timeout) as answer:   # noqa: S310 - loopback
        return answer.status, dict(answer.headers), answer.read()


def test_page_shows_the_published_frames(ros_domain: int, tmp_path: pathlib.Path) -> None:
    observer = Observer({'Eye': 'ImageDisplay'})
    try:
        with pattern_camera('Camera', 'yuv24'), \
                eye(['-i', 'Camera', '-d', 'web', '-p', '0'], display=None) as child:
            line = child.expect('shows Camera on http://', timeout=30)
            url = re.search(r'http://127\.0\.0\.1:\d+/', line)
            assert url, f'not on 127.0.0.1 by default: {line}'
            page = url.group(0)
            # The first frame (a long poll: answered when the Eye has one), with its index.
            code, headers, _ = fetch(page + 'frame.png?after=0', timeout=30)
            assert code == 200 and int(headers['X-Frame-Index']) >= 1

            shot = chromium_screenshot(page, tmp_path, (320, 280))
            k, mean, largest = which_frame(shot)
            assert mean <= MEAN_TOLERANCE and largest <= MAX_TOLERANCE, (k, mean, largest)

            # Clicks (in shown pixels) and keys, as the page's script posts them.
            assert fetch(page + 'click?x=100&y=50', method='POST')[0] == 204
            assert fetch(page + 'key?code=65', method='POST')[0] == 204
            observer.until(lambda o: (s := status(o)) is not None and s.click_count == 1
                           and s.key == 65, 'the click and the key in the status')
            last = status(observer)
            assert (last.click_x, last.click_y) == (100, 50)
            assert last.frames_shown >= 2              # our fetch and Chromium's page
            # Hidden: the page gets no frame (204) and says so.
            observer.request('Eye', visible=False)
            observer.until(lambda o: not o.infos['Eye'].visible, 'visible false in the info')
            code, headers, _ = fetch(page + 'frame.png?after=0')
            assert code == 204 and headers['X-Visible'] == '0'
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
