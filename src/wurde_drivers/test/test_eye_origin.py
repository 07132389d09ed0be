"""The Eye's page takes clicks and keys only from itself: a POST from another web page (its
Origin) or through another site's name (DNS rebinding: its Host) is refused and never reaches the
ImageDisplay status."""

from __future__ import annotations

import http.client
from collections.abc import Iterator

import pytest

from wurde_drivers.eye.frames import DisplaySettings, FrameStore
from wurde_drivers.eye.status import DisplayStatus
from wurde_drivers.eye.web import WebDisplay


@pytest.fixture
def web() -> Iterator[WebDisplay]:
    display = WebDisplay(FrameStore(DisplaySettings()), DisplayStatus(), port=0)
    display.open()
    try:
        yield display
    finally:
        display.close()


def _post(display: WebDisplay, path: str, headers: dict[str, str]) -> int:
    connection = http.client.HTTPConnection('127.0.0.1', display.port, timeout=10)
    try:
        connection.putrequest('POST', path, skip_host=True)
        for name, value in headers.items():
            connection.putheader(name, value)
        connection.putheader('Content-Length', '0')
        connection.endheaders()
        response = connection.getresponse()
        response.read()
        return response.status
    finally:
        connection.close()


def test_a_cross_origin_post_is_refused_and_the_page_own_is_taken(web: WebDisplay) -> None:
    own = f'127.0.0.1:{web.port}'
    assert _post(web, '/click?x=3&y=4', {'Host': own, 'Origin': 'http://evil.example'}) == 403
    assert _post(web, '/key?code=65', {'Host': own, 'Origin': 'null'}) == 403
    assert _post(web, '/key?code=65', {'Host': own, 'Origin': f'http://localhost:{web.port}'}) == 403
    assert web.status.snapshot().click_count == 0 and web.status.snapshot().key == 0
    assert _post(web, '/click?x=3&y=4', {'Host': own, 'Origin': f'http://{own}'}) == 204
    assert _post(web, '/key?code=66', {'Host': f'localhost:{web.port}',
                                       'Origin': f'http://localhost:{web.port}'}) == 204
    assert _post(web, '/key?code=67', {'Host': own}) == 204        # no browser: no Origin
    snapshot = web.status.snapshot()
    assert (snapshot.click_count, snapshot.click_x, snapshot.click_y, snapshot.key) == (1, 3, 4, 67)


def test_another_sites_name_for_the_loopback_is_refused(web: WebDisplay) -> None:
    rebound = f'evil.example:{web.port}'
    assert _post(web, '/click?x=1&y=1', {'Host': rebound, 'Origin': f'http://{rebound}'}) == 403
    assert _post(web, '/click?x=1&y=1', {'Host': '127.0.0.1:1', 'Origin': 'http://127.0.0.1:1'}) == 403
    assert _post(web, '/click?x=1&y=1', {'Host': '127.0.0.1:x'}) == 403
    connection = http.client.HTTPConnection('127.0.0.1', web.port, timeout=10)
    try:
        connection.request('GET', '/status.json', headers={'Host': rebound})
        assert connection.getresponse().status == 403
    finally:
        connection.close()
    assert web.status.snapshot().click_count == 0
