"""One module process: started without a shell, output to a log file, owned by one thread.

Every slow or racy action on a process — waiting for its exit, reaping it, the stop escalation
(grace for a commanded Quit, then SIGINT -> SIGTERM -> SIGKILL), writing the exit line and
closing the log — is done by the process's own *owner thread* and nowhere else.  The owner
blocks in ``select`` on a pidfd (readable when the process ends) and a wake-up pipe, so it sees
an exit the moment it happens and never polls.  Other threads (the MCP's supervision loop) only
read what the owner recorded (:attr:`ModuleProcess.exit_code`, :attr:`ModuleProcess.ended`),
ask for a stop (:meth:`ModuleProcess.stop`, returns at once) or send a signal through the pidfd
(:meth:`ModuleProcess.signal`, never to a reused pid).  So nothing the supervision loop calls
blocks, and no two threads ever reap the same process or close the same log.

Children ask the kernel to kill them when the MCP dies (``PR_SET_PDEATHSIG``), so no module is
orphaned whatever signal ends the MCP.
"""

from __future__ import annotations

import ctypes
import os
import pathlib
import select
import signal
import subprocess
import sys
import threading
import time

#: Default wait between escalation steps (s).
STOP_STEP_S = 3.0
_PR_SET_PDEATHSIG = 1
_ESCALATION = (signal.SIGINT, signal.SIGTERM, signal.SIGKILL)


def _die_with_parent() -> None:  # runs in the child between fork and exec
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    os.setpgid(0, 0)


class ModuleProcess:
    """A running (or finished) module process and the thread that owns it."""

    def __init__(self, name: str, argv: list[str], log_directory: str,
                 environment: dict[str, str] | None = None) -> None:
        """Start ``argv``, logging to ``<log_directory>/<name>.log``, with ``environment`` added
        to this process's environment."""
        self.name = name
        self.argv = argv
        log_dir = pathlib.Path(log_directory)
        log_dir.mkdir(parents=True, exist_ok=True)
        self.log_path = log_dir / f'{name}.log'
        self._log = open(self.log_path, 'ab')  # noqa: SIM115 - closed by the owner thread
        self._log.write(f'--- {time.strftime("%Y-%m-%d %H:%M:%S")} start: {argv}\n'.encode())
        self._log.flush()
        command = argv
        if argv[0].endswith('.py') or _is_python_script(argv[0]):
            command = [sys.executable, *argv]
        try:
            self.popen = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=self._log,
                                          stderr=subprocess.STDOUT, preexec_fn=_die_with_parent,
                                          close_fds=True, env={**os.environ, **(environment or {})})
        except OSError:
            self._log.close()
            raise
        self.pid = self.popen.pid
        self.started = time.monotonic()
        #: Monotonic time the owner saw the process end (``None`` while it runs).
        self.ended: float | None = None
        #: Exit code (negative: killed by that signal) once the owner reaped the process.
        self.exit_code: int | None = None
        self._exited = threading.Event()
        self._fd_lock = threading.Lock()  # guards _pidfd against use after close
        self._pidfd: int | None = os.pidfd_open(self.pid)
        self._wake_r, wake_w = os.pipe()
        self._wake_w: int | None = wake_w
        self._request_lock = threading.Lock()
        self._schedule: list[tuple[float, signal.Signals]] = []
        self._owner = threading.Thread(target=self._own, name=f'owner-{name}', daemon=True)
        self._owner.start()

    # -- what other threads may do ---------------------------------------------------------------
    def poll(self) -> int | None:
        """The exit code once the owner reaped the process, else ``None`` (never blocks)."""
        return self.exit_code

    def running(self) -> bool:
        return self.exit_code is None

    def stopping(self) -> bool:
        """Whether a stop escalation has been asked for and the process still runs."""
        with self._request_lock:
            return bool(self._schedule) and self.exit_code is None

    def signal(self, signum: int) -> None:
        """Send ``signum`` now (through the pidfd: a reaped process's pid is never hit)."""
        with self._fd_lock:
            if self._pidfd is None:
                return
            try:
                signal.pidfd_send_signal(self._pidfd, signum)
            except ProcessLookupError:
                pass

    def stop(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> None:
        """Ask the owner to stop the process: after ``grace_s`` (for a Quit already sent) SIGINT,
        then SIGTERM and SIGKILL ``step_s`` apart.  Returns at once; a second call can only
        bring the steps forward."""
        now = time.monotonic()
        steps = [(now + grace_s + i * step_s, sig) for i, sig in enumerate(_ESCALATION)]
        with self._request_lock:
            if self._schedule:
                steps = [(min(a[0], b[0]), a[1]) for a, b in zip(self._schedule, steps)]
            self._schedule = steps
        self._wake()

    def wait(self, timeout: float | None = None) -> int | None:
        """Wait up to ``timeout`` s for the owner to reap the process; its exit code or ``None``."""
        self._exited.wait(timeout)
        return self.exit_code

    def stop_and_wait(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> int:
        """:meth:`stop`, then wait for the end (bounded by the escalation itself)."""
        self.stop(step_s, grace_s)
        code = self.wait(grace_s + len(_ESCALATION) * step_s + 5.0)
        if code is None:  # SIGKILL did not end it within seconds: uninterruptible sleep
            raise subprocess.TimeoutExpired(self.argv, grace_s + 3 * step_s)
        return code

    # -- the owner thread ------------------------------------------------------------------------
    def _wake(self) -> None:
        with self._request_lock:  # the owner closes the pipe under this lock: no stale fd
            if self._wake_w is not None:
                os.write(self._wake_w, b'x')

    def _own(self) -> None:
        """Wait for the exit, run the escalation, then reap and close the log (and nothing else
        does any of these)."""
        assert self._pidfd is not None
        try:
            while True:
                with self._request_lock:
                    due = self._schedule[0][0] if self._schedule else None
                timeout = None if due is None else max(0.0, due - time.monotonic())
                readable, _, _ = select.select([self._pidfd, self._wake_r], [], [], timeout)
                if self._pidfd in readable:
                    break
                if self._wake_r in readable:
                    os.read(self._wake_r, 64)
                now = time.monotonic()
                with self._request_lock:
                    while self._schedule and self._schedule[0][0] <= now:
                        _, sig = self._schedule.pop(0)
                        self.signal(sig)
        finally:
            self.ended = time.monotonic()
            code = self.popen.wait()  # returns at once unless the loop above failed
            with self._fd_lock:
                fd, self._pidfd = self._pidfd, None
                if fd is not None:
                    os.close(fd)
            with self._request_lock:
                wake_w, self._wake_w = self._wake_w, None
                if wake_w is not None:
                    os.close(wake_w)
            os.close(self._wake_r)
        try:
            self._log.write(f'--- exit code {code}\n'.encode())
        finally:
            self._log.close()
        self.exit_code = code
        self._exited.set()


def _is_python_script(path: str) -> bool:
    """Whether ``path`` starts with a python shebang (run it with this interpreter's venv)."""
    try:
        with open(path, 'rb') as handle:
            first = handle.readline(200)
    except OSError:
        return False
    return first.startswith(b'#!') and b'python' in first
