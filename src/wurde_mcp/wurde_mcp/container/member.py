"""The MCP's side of a container: its process, and each module in it as the supervisor sees it.

:class:`Container` starts the container program (:mod:`.host`) when a module of it is to start and
none runs, sends it the module's command line and environment, and reads what it reports.
:class:`ContainedProcess` is one start of one module in it, with the interface of
:class:`wurde_mcp.process.ModuleProcess`: ``pid`` is the module thread's id (what its heartbeat
reports, unique per start: the supervisor's rule for late beats of an ended process holds),
``signal``/``stop`` ask the container to quit the module, and SIGKILL — a hung module's — kills
the container, which ends every module in it with the container's exit code.
"""

from __future__ import annotations

import json
import pathlib
import signal
import socket
import subprocess
import threading
import time
from typing import Any

from wurde_core.logger import g_error, g_info

from ..process import ESCALATION, STOP_STEP_S, ModuleProcess, escalation

#: The container program, found as a module's binary is.
CONTAINER_BINARY = 'wurde_mcp/container'
#: After its control line closes, how long a container may take to end before the MCP kills it.
END_WAIT_S = 30.0


class ContainedProcess:
    """One start of a module inside a container (the interface of ModuleProcess)."""

    def __init__(self, container: Container, process: ModuleProcess, name: str, seq: int,
                 argv: list[str], log_directory: str) -> None:
        self.name = name
        self.argv = argv
        self.seq = seq
        self.container = container
        #: The container process this start belongs to.
        self.process = process
        #: The module thread's id once the container reports it (in a cooperative container, a
        #: number above any pid, unique per start); the container's pid until then.
        self.pid = process.pid
        #: The kernel task that runs the module (/proc/TASK: its state and CPU time): its
        #: thread, or a cooperative container's hub thread; the container's pid until reported.
        self.task = process.pid
        self.started = time.monotonic()
        self.ended: float | None = None
        self.exit_code: int | None = None
        self._exited = threading.Event()
        self._cond = threading.Condition()
        self._schedule: list[tuple[float, signal.Signals]] = []
        self._escalator: threading.Thread | None = None
        self.log_path = pathlib.Path(log_directory) / f'{name}.log'
        self._note(f'start in container {container.name} (its log: {container.name}.log): {argv}')

    def _note(self, text: str) -> None:
        try:
            self.log_path.parent.mkdir(parents=True, exist_ok=True)
            with open(self.log_path, 'a', encoding='utf-8') as log:
                log.write(f'--- {time.strftime("%Y-%m-%d %H:%M:%S")} {text}\n')
        except OSError:
            pass

    def poll(self) -> int | None:
        return self.exit_code

    def running(self) -> bool:
        return self.exit_code is None

    def stopping(self) -> bool:
        with self._cond:
            return bool(self._schedule) and self.exit_code is None

    def signal(self, signum: int) -> None:
        """SIGINT and SIGTERM quit the module (as they would a module process); SIGKILL kills the
        container (a thread cannot be killed); any other signal goes to the container."""
        if self.exit_code is not None:
            return
        if signum in (signal.SIGINT, signal.SIGTERM):
            self.container.send(op='quit', name=self.name, seq=self.seq)
        else:
            self.process.signal(signum)

    def stop(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> None:
        """ModuleProcess's escalation: after ``grace_s`` a quit (SIGINT), then SIGTERM, then
        SIGKILL — the container's — ``step_s`` apart; returns at once."""
        with self._cond:
            self._schedule = escalation(step_s, grace_s, self._schedule)
            if self._escalator is None:
                self._escalator = threading.Thread(target=self._escalate, name=f'stop-{self.name}',
                                                   daemon=True)
                self._escalator.start()
            self._cond.notify_all()

    def _escalate(self) -> None:
        with self._cond:
            while self.exit_code is None and self._schedule:
                due, sig = self._schedule[0]
                left = due - time.monotonic()
                if left > 0:
                    self._cond.wait(left)
                    continue
                self._schedule.pop(0)
                self._cond.release()
                try:
                    self.signal(sig)
                finally:
                    self._cond.acquire()

    def wait(self, timeout: float | None = None) -> int | None:
        self._exited.wait(timeout)
        return self.exit_code

    def stop_and_wait(self, step_s: float = STOP_STEP_S, grace_s: float = 0.0) -> int:
        self.stop(step_s, grace_s)
        code = self.wait(grace_s + len(ESCALATION) * step_s + END_WAIT_S)
        if code is None:
            raise subprocess.TimeoutExpired(self.argv, grace_s + 3 * step_s)
        return code

    def _started(self, tid: int, task: int) -> None:
        self.pid = tid
        self.task = task

    def _end(self, code: int) -> None:
        with self._cond:
            if self.exit_code is not None:
                return
            self.ended = time.monotonic()
            self.exit_code = code
            self._cond.notify_all()
        self._note(f'exit code {code}')
        self._exited.set()


class Container:
    """A ``<container>`` of the MCP config: its process (started on demand) and its modules."""

    def __init__(self, name: str, binary: str, log_directory: str, environment: dict[str, str],
                 ros_arguments: list[str], *, quantum: float | None = None) -> None:
        """:param binary: the container program's path (``wurde_mcp/container``, found).
        :param environment: variables added to the container process's environment.
        :param ros_arguments: the MCP's ``--ros-args ...`` for the process's context.
        :param quantum: its modules take turns in one thread (``scheduling="cooperative"``),
            waking for deadlines at most once per ``quantum`` s; None: a thread each."""
        self.name = name
        self.quantum = quantum
        self.binary = binary
        self.log_directory = log_directory
        self.environment = environment
        self.ros_arguments = ros_arguments
        self.process: ModuleProcess | None = None
        self._socket: socket.socket | None = None
        self._members: dict[int, ContainedProcess] = {}
        self._seq = 0
        self._lock = threading.Lock()
        self._send_lock = threading.Lock()

    def start_module(self, name: str, binary: str, argv: list[str], env: dict[str, str]) -> ContainedProcess:
        """Start module ``name`` (its ``package/executable`` ``binary``, command line ``argv``,
        MCP variables ``env``) in the container, starting the container first if it does not run.

        :raises OSError: the container process cannot be started.
        """
        with self._lock:
            if self.process is None or not self.process.running():
                self._spawn()
            assert self.process is not None
            self._seq += 1
            member = ContainedProcess(self, self.process, name, self._seq, argv, self.log_directory)
            self._members[member.seq] = member
        self.send(op='start', name=name, seq=member.seq, binary=binary, argv=argv, env=env)
        return member

    def send(self, **message: Any) -> None:
        with self._send_lock:
            if self._socket is None:
                return
            try:
                self._socket.sendall(json.dumps(message).encode() + b'\n')
            except OSError:
                pass        # the container has ended: its reader ends every member

    def close(self, wait_s: float = 10.0) -> None:
        """End the container process (its modules quit first; :meth:`Supervisor.quit_all` has
        normally ended them already)."""
        with self._lock:
            process = self.process
        if process is not None and process.running():
            try:
                code = process.stop_and_wait(step_s=max(wait_s / 3, 0.5))
                g_info(f'MCP: container {self.name} ended (exit code {code})')
            except subprocess.TimeoutExpired:
                g_error(f'MCP: container {self.name} (pid {process.pid}) did not end after SIGKILL')

    def _spawn(self) -> None:
        ours, theirs = socket.socketpair()
        try:
            self.process = ModuleProcess(self.name, [self.binary, '-n', self.name, '--control',
                                                     str(theirs.fileno()),
                                                     *([] if self.quantum is None else
                                                       ['--cooperative', '--quantum', str(self.quantum)]),
                                                     *self.ros_arguments],
                                         self.log_directory, self.environment, pass_fds=(theirs.fileno(),))
        except OSError:
            ours.close()
            raise
        finally:
            theirs.close()
        with self._send_lock:
            self._socket = ours
        threading.Thread(target=self._read, args=(ours, self.process), name=f'container-{self.name}',
                         daemon=True).start()

    def _report(self, line: bytes) -> None:
        try:
            report = json.loads(line)
            member = self._members.get(int(report['seq']))
            if member is None:
                return
            if report['op'] == 'started':
                member._started(int(report['tid']), int(report.get('task', report['tid'])))
            elif report['op'] == 'ended':
                with self._lock:
                    self._members.pop(member.seq, None)
                member._end(int(report['code']))
        except (ValueError, KeyError, TypeError):
            return

    def _read(self, sock: socket.socket, process: ModuleProcess) -> None:
        """What the container reports, until its line closes; then every module still in it ends
        with the container's exit code."""
        try:
            with sock.makefile('rb') as reader:
                for line in reader:
                    self._report(line)
        except OSError:
            pass                            # reset by a killed container: its end, as an EOF
        code = process.wait(END_WAIT_S)
        if code is None:                     # closed its line but lives on: not ours any more
            process.signal(signal.SIGKILL)
            code = process.wait(END_WAIT_S)
        with self._lock:
            left = [m for m in self._members.values() if m.process is process]
            for member in left:
                self._members.pop(member.seq, None)
            if self.process is process:
                self.process = None
        with self._send_lock:
            if self._socket is sock:
                self._socket = None
        sock.close()
        for member in left:
            member._end(code if code is not None else -int(signal.SIGKILL))

