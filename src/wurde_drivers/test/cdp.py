"""Headless Chromium driven over the DevTools protocol on a pipe (``--remote-debugging-pipe``:
commands in on fd 3, answers out on fd 4, JSON messages ended by NUL) — the standard library
only, no chromedriver. The Eye's web test uses it to watch the page's script replace frames,
take a screenshot and click and type as a person would."""

from __future__ import annotations

import base64
import fcntl
import json
import os
import pathlib
import select
import subprocess
import time
from typing import Any

import cv2
import numpy as np
from screens import need

CHROMIUM = '/usr/bin/chromium'
#: Chromium's flags for a closed network and a fresh profile (no first-run, no updates, no GPU).
CHROMIUM_FLAGS = ('--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                  '--disable-background-networking', '--disable-component-update', '--disable-sync',
                  '--hide-scrollbars', '--force-device-scale-factor=1')


class Browser:
    """One headless Chromium with one page of ``size`` (CSS pixels = screen pixels).

    A context manager: leaving it closes the browser (and kills it if it does not go).
    """

    def __init__(self, directory: pathlib.Path, size: tuple[int, int]) -> None:
        to_child, self._out = os.pipe()
        self._in, from_child = os.pipe()
        # The child's ends moved to fds 10 and up, then to 3 and 4 by bash on exec (no
        # preexec_fn: the test process has threads).
        ends = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (to_child, from_child)]
        os.close(to_child)
        os.close(from_child)
        argv = [need(CHROMIUM, 'chromium'), *CHROMIUM_FLAGS, '--remote-debugging-pipe',
                f'--user-data-dir={directory / "chromium-profile"}',
                f'--window-size={size[0]},{size[1]}', 'about:blank']
        self.process = subprocess.Popen(
            ['/bin/bash', '-c', f'exec "$0" "$@" 3<&{ends[0]} 4>&{ends[1]} {ends[0]}<&- {ends[1]}>&-',
             *argv], pass_fds=ends, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL, env=dict(os.environ, HOME=str(directory)))
        for fd in ends:
            os.close(fd)
        self._buffer = b''
        self._next_id = 0
        self.session = ''
        try:
            targets = self.call('Target.getTargets')['targetInfos']
            page = next(t['targetId'] for t in targets if t['type'] == 'page')
            self.session = self.call('Target.attachToTarget', targetId=page, flatten=True,
                                     session=False)['sessionId']
            self.call('Emulation.setDeviceMetricsOverride', width=size[0], height=size[1],
                      deviceScaleFactor=1, mobile=False)
        except BaseException:
            self.close()
            raise

    def open(self, url: str) -> None:
        """Load ``url`` in the page (returns when the navigation started)."""
        self.call('Page.navigate', url=url)

    def call(self, method: str, timeout: float = 30.0, session: bool = True, **params: Any) -> Any:
        """Send one command (to the page unless ``session`` is False); its result.

        :raises AssertionError: on a protocol error or no answer within ``timeout``.
        """
        self._next_id += 1
        message: dict[str, Any] = {'id': self._next_id, 'method': method, 'params': params}
        if session and self.session:
            message['sessionId'] = self.session
        os.write(self._out, json.dumps(message).encode() + b'\0')
        deadline = time.monotonic() + timeout
        while True:
            while b'\0' in self._buffer:
                raw, self._buffer = self._buffer.split(b'\0', 1)
                answer = json.loads(raw)
                if answer.get('id') == self._next_id:
                    if 'error' in answer:
                        raise AssertionError(f'{method}: {answer["error"]}')
                    return answer.get('result', {})
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._in], [], [], max(0.0, left))
            chunk = os.read(self._in, 1 << 20) if ready else b''
            if not chunk:
                raise AssertionError(f'{method}: no answer from Chromium within {timeout} s')
            self._buffer += chunk

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page."""
        answer = self.call('Runtime.evaluate', expression=expression, returnByValue=True)
        return answer['result'].get('value')

    def screenshot(self) -> np.ndarray:
        """RGB pixels of the page as shown."""
        data = base64.b64decode(self.call('Page.captureScreenshot', format='png')['data'])
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)

    def click(self, x: int, y: int) -> None:
        """A left click at page pixel (x, y)."""
        for kind in ('mousePressed', 'mouseReleased'):
            self.call('Input.dispatchMouseEvent', type=kind, x=x, y=y, button='left', clickCount=1)

    def key(self, code: int, key: str) -> None:
        """Press and release one key (``code`` its DOM keyCode, ``key`` its name)."""
        for kind in ('keyDown', 'keyUp'):
            self.call('Input.dispatchKeyEvent', type=kind, windowsVirtualKeyCode=code, key=key)

    def close(self) -> None:
        try:
            self.call('Browser.close', timeout=5.0, session=False)
        except (AssertionError, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        for fd in (self._in, self._out):
            os.close(fd)

    def __enter__(self) -> 'Browser':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
