"""A keyboard program in a real pseudo-terminal: keys written to it, its screen read back."""

from __future__ import annotations

import os
import pty
import re
import subprocess
import sys
import threading
import time
from collections.abc import Sequence

ARROWS = {'up': '\x1b[A', 'down': '\x1b[B', 'right': '\x1b[C', 'left': '\x1b[D'}


class Terminal:
    """``argv`` run with a pty as its terminal (stdin, stdout, stderr)."""

    def __init__(self, argv: Sequence[str], env: dict[str, str]) -> None:
        master, slave = pty.openpty()
        self.process = subprocess.Popen([sys.executable, *argv], stdin=slave, stdout=slave, stderr=slave,
                                        env=env, start_new_session=True)
        os.close(slave)
        self.master = master
        self.screen = ''
        self._seen = 0
        self._changed = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while True:
            try:
                chunk = os.read(self.master, 4096).decode(errors='replace')
            except OSError:
                chunk = ''
            with self._changed:
                if not chunk:
                    self._changed.notify_all()
                    return
                self.screen += chunk
                self._changed.notify_all()

    def press(self, key: str) -> None:
        os.write(self.master, ARROWS.get(key, key).encode())

    def expect(self, pattern: str, timeout: float = 30.0) -> re.Match:
        """The first match of ``pattern`` in what the program printed since the last match."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                found = re.search(pattern, self.screen[self._seen:])
                if found:
                    self._seen += found.end()
                    return found
                left = deadline - time.monotonic()
                if left <= 0 or self.process.poll() is not None and not self._changed.wait(0.5):
                    raise AssertionError(f'{pattern!r} not printed within {timeout} s (exit '
                                         f'{self.process.poll()}); screen:\n{self.screen[-2000:]}')
                self._changed.wait(min(left, 0.5))

    def close(self) -> int | None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        os.close(self.master)
        return self.process.returncode
