"""A child process for tests: started with the test's environment, always reaped."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from collections.abc import Sequence


class ChildProcess:
    """Run ``argv`` (a Python module or script by default) as a real child process.

    Output goes to pipes read after :meth:`stop`.  Use as a context manager: leaving the block
    stops the child (SIGINT, then SIGKILL after ``timeout``) whatever happened in the test.
    """

    def __init__(self, argv: Sequence[str], *, env: dict[str, str] | None = None,
                 python: bool = True) -> None:
        command = [sys.executable, *argv] if python else list(argv)
        self.process = subprocess.Popen(
            command, env=dict(env if env is not None else os.environ),
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.stdout = ''
        self.stderr = ''
        self._stopped = False

    def stop(self, timeout: float = 10.0) -> int:
        """Ask the child to finish (SIGINT, stdin closed), kill it after ``timeout``; return its code.

        Idempotent; the child's output is in :attr:`stdout` and :attr:`stderr` afterwards.
        """
        if self._stopped:
            return self.process.returncode
        self._stopped = True
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            out, err = self.process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            out, err = self.process.communicate()
        self.stdout, self.stderr = out or '', err or ''
        return self.process.returncode

    def __enter__(self) -> 'ChildProcess':
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
