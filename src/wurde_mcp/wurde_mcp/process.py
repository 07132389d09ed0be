"""One module process: started without a shell, output to a log file, stopped by escalation.

Children ask the kernel to kill them when the MCP dies (``PR_SET_PDEATHSIG``), so no module is
orphaned whatever signal ends the MCP.  Stopping escalates SIGINT -> SIGTERM -> SIGKILL, waiting
:data:`STOP_STEP_S` between steps.
"""

from __future__ import annotations

import ctypes
import os
import threading
import pathlib
import signal
import subprocess
import sys
import time

STOP_STEP_S = 3.0
_PR_SET_PDEATHSIG = 1


def _die_with_parent() -> None:  # runs in the child between fork and exec
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    os.setpgid(0, 0)


class ModuleProcess:
    """A running (or finished) module process."""

    def __init__(self, name: str, argv: list[str], log_directory: str) -> None:
        self.name = name
        self.argv = argv
        log_dir = pathlib.Path(log_directory)
        log_dir.mkdir(parents=True, exist_ok=True)
        self.log_path = log_dir / f'{name}.log'
        self._log = open(self.log_path, 'ab')  # noqa: SIM115 - closed in reap()
        self._log.write(f'--- {time.strftime("%Y-%m-%d %H:%M:%S")} start: {argv}\n'.encode())
        self._log.flush()
        command = argv
        if argv[0].endswith('.py') or _is_python_script(argv[0]):
            command = [sys.executable, *argv]
        self.popen = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=self._log,
                                      stderr=subprocess.STDOUT, preexec_fn=_die_with_parent,
                                      close_fds=True)
        self.pid = self.popen.pid
        self.started = time.monotonic()
        self._stop_lock = threading.Lock()

    def poll(self) -> int | None:
        """The exit code once the process ended, else ``None``."""
        return self.popen.poll()

    def signal(self, signum: int) -> None:
        if self.popen.poll() is None:
            try:
                os.kill(self.pid, signum)
            except ProcessLookupError:
                pass

    def stop(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> int:
        """Wait ``grace_s`` for a commanded exit, then SIGINT, SIGTERM and SIGKILL, each after
        ``step_s``; return the exit code.  Safe to call from several threads: one escalates,
        the others wait for it."""
        with self._stop_lock:
            if self.popen.poll() is not None:
                return self.reap(None)
            try:
                return self.reap(grace_s)
            except subprocess.TimeoutExpired:
                pass
            for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
                self.signal(signum)
                try:
                    return self.reap(step_s)
                except subprocess.TimeoutExpired:
                    continue
            return self.reap(None)

    def reap(self, timeout: float | None = 0.0) -> int:
        """Wait for the exit (raises ``TimeoutExpired``) and close the log."""
        code = self.popen.wait(timeout=timeout)
        if not self._log.closed:
            self._log.flush()
            self._log.write(f'--- exit code {code}\n'.encode())
            self._log.close()
        return code


def _is_python_script(path: str) -> bool:
    """Whether ``path`` starts with a python shebang (run it with this interpreter's venv)."""
    try:
        with open(path, 'rb') as handle:
            first = handle.readline(200)
    except OSError:
        return False
    return first.startswith(b'#!') and b'python' in first
