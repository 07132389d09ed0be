"""The Eye's web page: where there is no X display, the images are shown on a local page (guide 7.8).

One page (``/``) with an ``<img>`` that the page's script replaces as soon as the Eye has a
newer frame: a long poll of ``/frame.png?after=N``, so no frame is fetched twice and none waits
for a timer.  ``/status.json`` tells the state; ``/click`` and ``/key`` (POST) bring the user's
clicks and keys back into ImageDisplay's data.  docs/wurde-drivers.md ("eye.web") lists the paths,
their answers and headers.

The server binds 127.0.0.1 unless told otherwise; nothing here reaches beyond the machine by
default.  Before changing the request handling, keep both guards: only the page itself may send
clicks and keys (a POST whose ``Origin`` is another site's gets 403), and on a loopback address
every request must name a loopback host in ``Host`` (no DNS rebinding of another site's name to
127.0.0.1).
"""

from __future__ import annotations

import dataclasses
import html
import http.server
import ipaddress
import json
import socket
import threading
import urllib.parse
from typing import Any

from .frames import Frame, FrameStore
from .status import DisplayStatus

__all__ = ['DEFAULT_ADDRESS', 'DEFAULT_PORT', 'LONG_POLL_S', 'WebDisplay']

DEFAULT_ADDRESS = '127.0.0.1'
DEFAULT_PORT = 8090
#: Longest wait of one ``/frame.png?after=N`` (s); the page asks again at once.
LONG_POLL_S = 5.0

_PAGE = """<!doctype html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>
html, body {{ margin: 0; padding: 0; background: #000; color: #ccc; font: 12px sans-serif; }}
img {{ display: block; }}
#caption {{ padding: 4px; }}
</style></head>
<body><img id="frame" src="/frame.png" alt="">
<div id="caption">{title}</div>
<script>
const img = document.getElementById('frame');
const caption = document.getElementById('caption');
let index = 0;
async function next() {{
  try {{
    const r = await fetch('/frame.png?after=' + index, {{cache: 'no-store'}});
    const hidden = r.headers.get('X-Visible') === '0';
    img.style.visibility = hidden ? 'hidden' : 'visible';
    if (r.status === 200) {{
      index = Number(r.headers.get('X-Frame-Index'));
      const title = decodeURIComponent(r.headers.get('X-Title') || '');
      const url = URL.createObjectURL(await r.blob());
      const old = img.src;
      img.src = url;
      if (old.startsWith('blob:')) URL.revokeObjectURL(old);
      document.title = title;
      caption.textContent = title + ' - frame ' + r.headers.get('X-Source-Frame');
      document.body.dataset.frame = index;
    }}
  }} catch (e) {{
    await new Promise(done => setTimeout(done, 1000));   // the Eye is gone or restarting
  }}
  setTimeout(next, 0);
}}
img.addEventListener('click', e => fetch(
  '/click?x=' + Math.floor(e.offsetX) + '&y=' + Math.floor(e.offsetY), {{method: 'POST'}}));
document.addEventListener('keydown', e => fetch('/key?code=' + e.keyCode, {{method: 'POST'}}));
next();
</script></body></html>
"""


class WebDisplay:
    """An HTTP server on ``address:port`` (port 0: any free one) showing ``store``'s frames.

    :meth:`open` binds and starts the server thread (raises ``OSError`` when the port is taken);
    :meth:`close` stops it (idempotent). The page's threads only read the store and write the
    status, so the module's loop is never blocked by a browser.
    """

    def __init__(self, store: FrameStore, status: DisplayStatus, *,
                 address: str = DEFAULT_ADDRESS, port: int = DEFAULT_PORT) -> None:
        self.store, self.status = store, status
        self.address, self.port = address, port
        self._server: http.server.ThreadingHTTPServer | None = None
        self._thread: threading.Thread | None = None

    @property
    def url(self) -> str:
        host = f'[{self.address}]' if ':' in self.address else self.address
        return f'http://{host}:{self.port}/'

    def open(self) -> None:
        handler = type('Handler', (_Handler,), {'display': self})
        server_class = _Server6 if ':' in self.address else http.server.ThreadingHTTPServer
        self._server = server_class((self.address, self.port), handler)
        self._server.daemon_threads = True
        self.port = int(self._server.server_address[1])
        self._thread = threading.Thread(target=self._server.serve_forever, name='eye-web',
                                        kwargs={'poll_interval': 0.2}, daemon=True)
        self._thread.start()

    def show(self, frame: Frame) -> None:
        """Nothing to do: the page fetches frames from the store itself."""

    def pump(self) -> None:
        """Nothing to do: the server runs in its own thread."""

    def close(self) -> None:
        server, self._server = self._server, None
        if server is None:
            return
        self.store.close()
        server.shutdown()
        server.server_close()
        if self._thread is not None:
            self._thread.join(timeout=2.0)


def _is_loopback(host: str) -> bool:
    if host == 'localhost':
        return True
    try:
        return ipaddress.ip_address(host.strip('[]')).is_loopback
    except ValueError:
        return False


class _Server6(http.server.ThreadingHTTPServer):
    """The server on an IPv6 address (``-b ::1``)."""

    address_family = socket.AF_INET6


class _Handler(http.server.BaseHTTPRequestHandler):
    display: WebDisplay
    protocol_version = 'HTTP/1.1'

    def log_message(self, format: str, *args: Any) -> None:   # noqa: A002 - the base's name
        """Quiet: the page polls all the time."""

    def _send(self, code: int, body: bytes = b'', content_type: str = 'text/plain',
              headers: dict[str, str] | None = None) -> None:
        self.send_response(code)
        self.send_header('Content-Type', content_type)
        self.send_header('Content-Length', str(len(body)))
        self.send_header('Cache-Control', 'no-store')
        for name, value in (headers or {}).items():
            self.send_header(name, value)
        self.end_headers()
        if body and self.command != 'HEAD':
            self.wfile.write(body)

    def _query(self) -> tuple[str, dict[str, str]]:
        url = urllib.parse.urlsplit(self.path)
        return url.path, {k: v[-1] for k, v in urllib.parse.parse_qs(url.query).items()}

    def _host_allowed(self) -> bool:
        """On a loopback address, ``Host`` must be a loopback name with this server's port."""
        if not _is_loopback(self.display.address):
            return True
        host = urllib.parse.urlsplit(f'//{self.headers.get("Host", "")}')
        try:
            return _is_loopback(host.hostname or '') and host.port in (None, self.display.port)
        except ValueError:      # a port that is not a number
            return False

    def _origin_allowed(self) -> bool:
        """A browser's POST carries ``Origin``: it must be this page's (``Host`` as asked)."""
        origin = self.headers.get('Origin')
        return origin is None or origin == f'http://{self.headers.get("Host", "")}'

    def _refuse_foreign(self, post: bool) -> bool:
        if self._host_allowed() and (not post or self._origin_allowed()):
            return False
        self._send(403, b'not from this page\n')
        return True

    def do_GET(self) -> None:   # noqa: N802 - http.server's name
        if self._refuse_foreign(post=False):
            return
        path, query = self._query()
        store, settings = self.display.store, self.display.store.settings
        if path == '/':
            page = _PAGE.format(title=html.escape(settings.title))
            self._send(200, page.encode(), 'text/html; charset=utf-8')
        elif path == '/frame.png':
            self._frame(query)
        elif path == '/status.json':
            frame = store.latest()
            body = {'frame': frame.index if frame else 0,
                    'source_frame': frame.source_index if frame else None,
                    'width': frame.width if frame else 0, 'height': frame.height if frame else 0,
                    **dataclasses.asdict(settings),
                    **dataclasses.asdict(self.display.status.snapshot())}
            self._send(200, json.dumps(body).encode(), 'application/json')
        else:
            self._send(404, b'not found\n')

    def _frame(self, query: dict[str, str]) -> None:
        store = self.display.store
        try:
            after = int(query.get('after', '-1'))
        except ValueError:
            self._send(400, b'after must be a number\n')
            return
        frame = store.latest() if after < 0 else None
        if frame is None:
            frame = store.wait_newer(max(after, 0), LONG_POLL_S)
        settings = store.settings
        headers = {'X-Visible': '1' if settings.visible else '0',
                   'X-Title': urllib.parse.quote(settings.title)}
        if frame is None or not settings.visible:
            self._send(204, headers=headers)
            return
        body = store.png(frame)
        self.display.status.shown(frame.index)
        self._send(200, body, 'image/png', {**headers, 'X-Frame-Index': str(frame.index),
                                            'X-Source-Frame': str(frame.source_index)})

    def do_POST(self) -> None:   # noqa: N802 - http.server's name
        if self._refuse_foreign(post=True):
            return
        path, query = self._query()
        scale = self.display.store.settings.scale
        try:
            if path == '/click':
                self.display.status.click(int(int(query['x']) / scale),
                                          int(int(query['y']) / scale))
            elif path == '/key':
                self.display.status.key(int(query['code']))
            else:
                self._send(404, b'not found\n')
                return
        except (KeyError, ValueError):
            self._send(400, b'bad or missing parameters\n')
            return
        self._send(204)
