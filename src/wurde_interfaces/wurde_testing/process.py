"""A child process for tests: started with the test's environment, always reaped.

Its output is read line by line by background threads, so a test can wait for a line with a
deadline (:meth:`ChildProcess.expect`) and send it commands on stdin (:meth:`ChildProcess.send`).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from typing import IO


class ChildProcess:
    """Run ``argv`` (with the current Python unless ``python=False``) as a real child process.

    Use as a context manager: leaving the block stops the child (SIGINT, then SIGKILL after
    ``timeout``) whatever happened in the test.
    """

    def __init__(self, argv: Sequence[str], *, env: dict[str, str] | None = None,
                 python: bool = True, cwd: str | os.PathLike[str] | None = None) -> None:
        """Start the child now, its stdin, stdout and stderr piped (text, line-buffered).

        :param argv: the command (after ``python``, e.g. ``['-m', 'module', ...]``).
        :param env: the child's whole environment; None: this process's.
        :param python: run ``argv`` with the current Python interpreter; False: ``argv`` is the
            whole command line.
        :param cwd: the child's working directory; None: this process's.
        """
        command = [sys.executable, *argv] if python else list(argv)
        self.process = subprocess.Popen(
            command, env=dict(env if env is not None else os.environ), cwd=cwd,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            bufsize=1)
        self._lines: list[str] = []
        self._errors: list[str] = []
        self._seen = 0
        self._changed = threading.Condition()
        self._readers = [threading.Thread(target=self._read, args=(self.process.stdout, self._lines),
                                          daemon=True),
                         threading.Thread(target=self._read, args=(self.process.stderr, self._errors),
                                          daemon=True)]
        for reader in self._readers:
            reader.start()
        self._stopped = False

    def _read(self, stream: IO[str] | None, into: list[str]) -> None:
        assert stream is not None
        for line in stream:
            with self._changed:
                into.append(line.rstrip('\n'))
                self._changed.notify_all()

    @property
    def stdout(self) -> str:
        with self._changed:
            return '\n'.join(self._lines) + ('\n' if self._lines else '')

    @property
    def stderr(self) -> str:
        with self._changed:
            return '\n'.join(self._errors) + ('\n' if self._errors else '')

    def send(self, line: str) -> None:
        """Write one line to the child's stdin.

        :param line: the text; a newline is added.
        """
        assert self.process.stdin is not None
        self.process.stdin.write(line + '\n')
        self.process.stdin.flush()

    def expect(self, text: str, timeout: float = 20.0) -> str:
        """The first not yet consumed stdout line containing ``text``; the lines before it are
        consumed too.

        :param text: a substring of the line wanted.
        :param timeout: the longest wait, in seconds (shorter when the child has ended).
        :raises AssertionError: with the child's output when no such line comes in time.
        """
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                for index in range(self._seen, len(self._lines)):
                    if text in self._lines[index]:
                        self._seen = index + 1
                        return self._lines[index]
                remaining = deadline - time.monotonic()
                if remaining <= 0 or (self.process.poll() is not None and not self._alive_reader()):
                    raise AssertionError(
                        f'no line with {text!r} within {timeout} s (exit code '
                        f'{self.process.poll()})\nstdout:\n{chr(10).join(self._lines)}\n'
                        f'stderr:\n{chr(10).join(self._errors)}')
                self._changed.wait(min(remaining, 0.1))

    def _alive_reader(self) -> bool:
        return any(reader.is_alive() for reader in self._readers)

    def stop(self, timeout: float = 10.0) -> int:
        """Ask the child to finish (SIGINT, stdin closed), kill it after ``timeout``; return its code.

        Idempotent; the child's output stays in :attr:`stdout` and :attr:`stderr`.

        :param timeout: seconds to wait after SIGINT before SIGKILL.
        """
        if self._stopped:
            return self.process.returncode
        self._stopped = True
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            if self.process.stdin:
                self.process.stdin.close()
        except OSError:
            pass
        try:
            self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        for reader in self._readers:
            reader.join(timeout=5)
        return self.process.returncode

    def __enter__(self) -> 'ChildProcess':
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


def find_executable(package: str, name: str) -> str:
    """``lib/<package>/<name>`` under the first ament prefix that has it (where `ros2 run` looks).

    :param package: the ROS package.
    :param name: the executable's name.
    :raises AssertionError: when it is not installed (the test should fail, not skip).
    """
    import pathlib
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        path = pathlib.Path(prefix) / 'lib' / package / name
        if path.is_file():
            return str(path)
    raise AssertionError(f'{name} is not installed under lib/{package}')
