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
orphaned whatever signal ends the MCP.  No Python code runs between fork and exec (the MCP is
multi-threaded, and Python's documentation warns that ``preexec_fn`` can deadlock the child
there): the child execs a small launcher (:data:`_LAUNCHER`, a fresh interpreter) that makes the
request and execs the module, after checking that the MCP did not die before the request took
hold; its own process group comes from ``subprocess`` itself (``process_group=0``, or a new
session on Python 3.10).
"""

from __future__ import annotations

import errno
import math
import os
import pathlib
import select
import shutil
import signal
import subprocess
import sys
import threading
import time

from .progress import where_threads_wait

#: Default wait between escalation steps (s).
STOP_STEP_S = 3.0
ESCALATION = (signal.SIGINT, signal.SIGTERM, signal.SIGKILL)

#: Run as ``python -I -c _LAUNCHER MCP_PID EXEC_FD COMMAND...``: SIGKILL when the MCP's spawning
#: thread ends (prctl PR_SET_PDEATHSIG = 1, kept across exec), exit 1 if the MCP is already gone
#: (the launcher was re-parented before the request took hold), then exec the module in its
#: place; ``EXEC_FD`` closes on that exec (close-on-exec), which tells the owner the module runs.
_LAUNCHER = (
    'import ctypes, os, signal, sys\n'
    'ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)\n'
    'if os.getppid() != int(sys.argv[1]):\n'
    '    os._exit(1)\n'
    'os.set_inheritable(int(sys.argv[2]), False)\n'
    'try:\n'
    '    os.execvp(sys.argv[3], sys.argv[3:])\n'
    'except OSError as error:\n'
    '    sys.stderr.write(f"cannot start {sys.argv[3]}: {error}\\n")\n'
    '    os._exit(127)\n')
def escalation(step_s: float, grace_s: float, current: list[tuple[float, signal.Signals]]
               ) -> list[tuple[float, signal.Signals]]:
    """The stop escalation's steps from now, ``(monotonic time, signal)``: SIGINT after ``grace_s``,
    then SIGTERM and SIGKILL ``step_s`` apart; with ``current`` steps already asked for, each step
    the earlier of the two (a second stop only brings them forward)."""
    now = time.monotonic()
    steps = [(now + grace_s + i * step_s, sig) for i, sig in enumerate(ESCALATION)]
    if current:
        steps = [(min(a[0], b[0]), a[1]) for a, b in zip(current, steps)]
    return steps


#: The child's own process group, set by subprocess without Python code in the child.
_GROUP = {'process_group': 0} if sys.version_info >= (3, 11) else {'start_new_session': True}


class ModuleProcess:
    """A running (or finished) module process and the thread that owns it."""

    def __init__(self, name: str, argv: list[str], log_directory: str,
                 environment: dict[str, str] | None = None, pass_fds: tuple[int, ...] = ()) -> None:
        """Start ``argv``, logging to ``<log_directory>/<name>.log``, with ``environment`` added
        to this process's environment.

        :param name: the module's name: the log file's and the owner thread's.
        :param argv: the command, the binary first (a Python script runs with this interpreter);
            no shell.
        :param log_directory: the directory of the log (made if missing); output is appended.
        :param environment: variables added to this process's environment (None: none).
        :param pass_fds: file descriptors the process inherits (a container's control socket).
        :raises OSError: the binary is not an executable file, or the process cannot be started.
        """
        self.name = name
        self.argv = argv
        log_dir = pathlib.Path(log_directory)
        log_dir.mkdir(parents=True, exist_ok=True)
        self.log_path = log_dir / f'{name}.log'
        self._log = open(self.log_path, 'ab')  # noqa: SIM115 - closed by the owner thread
        self._stop_asked = math.nan
        self._log.write(f'--- {time.strftime("%Y-%m-%d %H:%M:%S")} start: {argv}\n'.encode())
        self._log.flush()
        command = argv
        if argv[0].endswith('.py') or _is_python_script(argv[0]):
            command = [sys.executable, *argv]
        env = {**os.environ, **(environment or {})}
        exec_r, exec_w = os.pipe()
        try:
            if shutil.which(command[0], path=env.get('PATH')) is None:   # refused here, as exec would
                raise FileNotFoundError(errno.ENOENT, 'not an executable file found', command[0])
            self.popen = subprocess.Popen([sys.executable, '-I', '-c', _LAUNCHER, str(os.getpid()), str(exec_w),
                                           *command],
                                          stdin=subprocess.DEVNULL, stdout=self._log, stderr=subprocess.STDOUT,
                                          close_fds=True, pass_fds=(exec_w, *pass_fds), env=env, **_GROUP)
        except OSError:
            self._log.close()
            os.close(exec_r)
            raise
        finally:
            os.close(exec_w)
        #: Read end of the launcher's exec pipe until the module has been exec'd (EOF).
        self._exec_r: int | None = exec_r
        #: Signals asked for before the module was exec'd, sent by the owner once it is.
        self._early: list[int] = []
        self.pid = self.popen.pid
        #: The kernel task whose /proc entry tells the module's state and CPU time: the process.
        self.task = self.pid
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
        """Send ``signum`` now (through the pidfd: a reaped process's pid is never hit); to a
        process still in its launcher, as soon as the module is exec'd.

        :param signum: the signal's number; nothing is sent to a process already reaped.
        """
        with self._fd_lock:
            if self._pidfd is None:
                return
            if self._exec_r is not None:
                self._early.append(signum)
                return
            try:
                signal.pidfd_send_signal(self._pidfd, signum)
            except ProcessLookupError:
                pass

    def stop(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> None:
        """Ask the owner to stop the process: after ``grace_s`` (for a Quit already sent) SIGINT,
        then SIGTERM and SIGKILL ``step_s`` apart.  Returns at once; a second call can only
        bring the steps forward.

        :param step_s: the wait between two signals (s).
        :param grace_s: the wait before SIGINT (s), for a module already told to Quit.
        """
        with self._request_lock:
            if not self._schedule:
                self._stop_asked = time.monotonic()
            self._schedule = escalation(step_s, grace_s, self._schedule)
        self._wake()

    def wait(self, timeout: float | None = None) -> int | None:
        """Wait up to ``timeout`` s for the owner to reap the process; its exit code or ``None``.

        :param timeout: the longest wait (s); None: until it is reaped.
        :returns: the exit code (negative: killed by that signal), or None if it still runs.
        """
        self._exited.wait(timeout)
        return self.exit_code

    def stop_and_wait(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> int:
        """:meth:`stop`, then wait for the end (bounded by the escalation itself).

        :param step_s: the wait between two signals (s).
        :param grace_s: the wait before SIGINT (s).
        :returns: the exit code.
        :raises subprocess.TimeoutExpired: not even SIGKILL ended it within seconds.
        """
        self.stop(step_s, grace_s)
        code = self.wait(grace_s + len(ESCALATION) * step_s + 5.0)
        if code is None:  # SIGKILL did not end it within seconds: uninterruptible sleep
            raise subprocess.TimeoutExpired(self.argv, grace_s + 3 * step_s)
        return code

    # -- the owner thread ------------------------------------------------------------------------
    def _note_signal(self, signum: int, now: float) -> None:
        """Say in the module's log which signal of a stop it gets, and where its threads wait:
        a module that does not end when asked shows what it was stuck in (its last words before
        a SIGKILL are otherwise lost)."""
        where = where_threads_wait(self.popen.pid)
        self._log.write(f'--- {signal.Signals(signum).name} {now - self._stop_asked:.1f} s after the stop '
                        f'was asked; its threads: {where or "gone"}\n'.encode())
        self._log.flush()

    def _executed(self) -> None:
        """The launcher exec'd the module (or ended): send what was asked for meanwhile."""
        with self._fd_lock:
            os.close(self._exec_r)  # type: ignore[arg-type]
            self._exec_r = None
            early, self._early = self._early, []
        for signum in early:
            self.signal(signum)

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
                watched = [self._pidfd, self._wake_r] + ([self._exec_r] if self._exec_r is not None else [])
                readable, _, _ = select.select(watched, [], [], timeout)
                if self._exec_r is not None and self._exec_r in readable and not os.read(self._exec_r, 64):
                    self._executed()
                if self._pidfd in readable:
                    break
                if self._wake_r in readable:
                    os.read(self._wake_r, 64)
                now = time.monotonic()
                with self._request_lock:
                    while self._schedule and self._schedule[0][0] <= now:
                        _, sig = self._schedule.pop(0)
                        self._note_signal(sig, now)
                        self.signal(sig)
        finally:
            self.ended = time.monotonic()
            code = self.popen.wait()  # returns at once unless the loop above failed
            with self._fd_lock:
                if self._exec_r is not None:
                    os.close(self._exec_r)
                    self._exec_r = None
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
