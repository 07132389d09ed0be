"""The container program: several modules in one process (issue 39's ``<container>``).

The MCP starts ``container -n NAME --control FD [--cooperative [--quantum S]] [--ros-args ...]``
and talks to it over the socket ``FD`` (one JSON object per line).  It asks ``{"op": "start",
"name", "seq", "binary", "argv", "env"}`` and ``{"op": "quit", "name", "seq"}``; the container
answers ``{"op": "started", "name", "seq", "tid", "task"}`` (the module's pid, and the kernel task
that runs it) and ``{"op": "ended", "name", "seq", "code"}``.

Each module runs in a thread of its own (with ``--cooperative``, a task of one hub thread:
:mod:`wurde_core.cooperative`): the container finds the ``main(argv)`` of the module's
``package/executable`` (its console script) and calls it with the module's command line, inside
a :class:`wurde_core.module_context.ModuleContext` that holds what would be the module process's
own — the MCP's environment variables for it, its role configuration and logger, and the
container's rclpy context, so that every contained node shares one DDS participant.  What a
module's ``main`` returns (or raises: exit code 1, with the traceback in the container's log) is
its exit code; the MCP restarts it by its usual rules, here, in the same process.

What a process would give each module, a container cannot: the modules share the interpreter (a
module that hangs the interpreter or leaks memory takes the others with it), the log (the
container's, each line as the module prints it), and the kill — the MCP's SIGKILL of a contained
module kills the container, and the MCP starts every module of it again (those with a resume
file take up their state).  SIGINT or SIGTERM to the container quits every module, then it ends.
"""

from __future__ import annotations

import argparse
import builtins
import ctypes
import importlib
import importlib.metadata
import json
import os
import signal
import socket
import sys
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.signals import SignalHandlerOptions
from wurde_core import cooperative, module_context
from wurde_core.comms_manager import skip_final_collection
from wurde_core.ros_adaptor import WaiterGroup

#: The longest wait for the modules to end after a quit of the whole container (s).
QUIT_WAIT_S = 20.0
#: Held through every import in the container: Python's per-module import locks let two threads
#: that import one package with import cycles inside it (numpy does) see it half made ("cannot
#: import name ... from partially initialized module"), which modules starting together do.
IMPORT_LOCK = threading.RLock()
#: prctl(2)'s option that names the calling thread.
PR_SET_NAME = 15
#: What a module of a cooperative container reports as its pid: this plus its start's number
#: (above any Linux pid, so that nobody takes it for a process; unique per start, as the MCP's
#: rule for late heartbeats of an ended start needs).
COOPERATIVE_PID_BASE = 1 << 30
#: The container's exit code when its hub fails (the MCP starts its modules again).
HUB_FAILED = 70


def name_os_thread(name: str) -> None:
    """Give the calling thread ``name`` (its first 15 bytes, Linux's limit) as the kernel knows it,
    so that ``top -H``, ``ps -L`` and /proc/PID/task/TID/comm tell the contained modules apart
    (``bench/footprint.py`` measures each one's CPU by it).  Nothing happens where the C library
    has no ``prctl``."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_NAME, ctypes.c_char_p(name.encode(errors='replace')[:15]), 0, 0, 0)
    except (OSError, AttributeError):
        pass


def serialize_imports() -> None:
    """Make every ``import`` statement of this process take :data:`IMPORT_LOCK` (reentrant: an
    import inside an import goes on).  A module whose import waits on another thread's import
    would hang: none of ours does."""
    original = builtins.__import__

    def locked_import(*args: Any, **kwargs: Any) -> Any:
        with IMPORT_LOCK:
            return original(*args, **kwargs)
    builtins.__import__ = locked_import


def find_main(binary: str) -> Callable[[list[str]], Any]:
    """The ``main`` of ``package/executable`` (its console-script entry point), or the function
    of ``python.module:function`` (a module not installed as a program, e.g. a user's own).

    :raises LookupError: naming what is missing.
    """
    with IMPORT_LOCK:
        if ':' in binary:
            module_name, _, function = binary.partition(':')
            try:
                found = getattr(importlib.import_module(module_name), function)
            except (ImportError, AttributeError) as error:
                raise LookupError(f'cannot import {binary}: {error}') from error
            return found
        package, _, executable = binary.partition('/')
        try:
            entry_points = importlib.metadata.distribution(package).entry_points
        except importlib.metadata.PackageNotFoundError as error:
            raise LookupError(f'no installed package "{package}"') from error
        for entry in entry_points:
            if entry.group == 'console_scripts' and entry.name == executable:
                return entry.load()
        raise LookupError(f'package "{package}" has no Python program "{executable}"')


class Host:
    """The container's modules and its line to the MCP."""

    def __init__(self, name: str, control: socket.socket, ros_arguments: list[str], *,
                 quantum: float | None = None) -> None:
        """:param quantum: run the modules as tasks of one hub thread (:mod:`wurde_core.cooperative`)
        that wakes for deadlines at most once per ``quantum`` s; None: a thread each."""
        self.name = name
        self.control = control
        self.context = Context()
        rclpy.init(args=['wurde', *ros_arguments], context=self.context,
                   signal_handler_options=SignalHandlerOptions.NO)
        self.modules: dict[tuple[str, int], tuple[module_context.ModuleContext, threading.Thread | None]] = {}
        self._lock = threading.Lock()
        self._send_lock = threading.Lock()
        self.quitting = threading.Event()
        self.hub: cooperative.Hub | None = None
        self._hub_thread: threading.Thread | None = None
        if quantum is not None:
            self.hub = cooperative.Hub(WaiterGroup(self.context), quantum)
            cooperative.patch_time_sleep()
            running = threading.Event()

            def run_hub() -> None:
                name_os_thread(f'hub-{name}')
                assert self.hub is not None
                self.hub.call_soon(running.set)
                try:
                    self.hub.run()
                except BaseException:   # noqa: BLE001 - without its hub the container is dead
                    traceback.print_exc()
                    sys.stderr.flush()
                    os._exit(HUB_FAILED)
            self._hub_thread = threading.Thread(target=run_hub, name=f'hub-{name}', daemon=True)
            self._hub_thread.start()
            running.wait()

    def send(self, **message: Any) -> None:
        with self._send_lock:
            try:
                self.control.sendall(json.dumps(message).encode() + b'\n')
            except OSError:
                pass                        # the MCP is gone: the modules quit on the EOF

    def start(self, name: str, seq: int, binary: str, argv: list[str], env: dict[str, str]) -> None:
        context = module_context.ModuleContext(name, dict(env), self.context)
        begun = threading.Event()
        args = (context, seq, binary, argv, begun)
        if self.hub is not None:
            with self._lock:
                self.modules[(name, seq)] = (context, None)
            self.hub.call_soon(self.hub.spawn, name, self._run, *args)
            begun.wait()
            self.send(op='started', name=name, seq=seq, tid=context.thread_id, task=self.hub.thread_id)
            return
        thread = threading.Thread(target=self._run, args=args, name=f'module-{name}', daemon=True)
        with self._lock:
            self.modules[(name, seq)] = (context, thread)
        thread.start()
        begun.wait()
        self.send(op='started', name=name, seq=seq, tid=context.thread_id, task=context.thread_id)

    def quit(self, name: str, seq: int) -> None:
        with self._lock:
            entry = self.modules.get((name, seq))
        if entry is not None:
            entry[0].request_quit()

    def quit_all(self) -> None:
        self.quitting.set()
        with self._lock:
            entries = list(self.modules.values())
        for context, _ in entries:
            context.request_quit()

    def _run(self, context: module_context.ModuleContext, seq: int, binary: str, argv: list[str],
             begun: threading.Event) -> None:
        if self.hub is None:
            name_os_thread(context.name)
            module_context.enter(context)
        else:
            module_context.enter(context, COOPERATIVE_PID_BASE + seq)
        begun.set()
        code: int = 0
        try:
            code = _exit_code(find_main(binary)(argv))
        except SystemExit as exit_:
            code = _exit_code(exit_.code)
        except LookupError as error:
            print(f'container {self.name}: cannot run {context.name}: {error}', file=sys.stderr, flush=True)
            code = 127
        except BaseException:       # noqa: BLE001 - a module's crash is its exit, not the container's
            print(f'container {self.name}: {context.name} raised:', file=sys.stderr, flush=True)
            traceback.print_exc()
            sys.stderr.flush()
            code = 1
        finally:
            manager = context.manager
            if manager is not None:     # a module that raised left its node: free it for the next
                try:
                    manager.clean_up(wait=False)
                except Exception:   # noqa: BLE001 - report the module's end whatever its clean-up did
                    traceback.print_exc()
            module_context.leave()
            with self._lock:
                self.modules.pop((context.name, seq), None)
            self.send(op='ended', name=context.name, seq=seq, code=code)

    def serve(self) -> None:
        """Follow the MCP's requests until it closes the line or the container is told to quit."""
        reader = self.control.makefile('rb')
        for line in reader:
            try:
                request = json.loads(line)
                op = request['op']
                if op == 'start':
                    self.start(request['name'], int(request['seq']), request['binary'],
                               [str(a) for a in request['argv']],
                               {str(k): str(v) for k, v in request['env'].items()})
                elif op == 'quit':
                    self.quit(request['name'], int(request['seq']))
                else:
                    raise ValueError(f'unknown op {op!r}')
            except (ValueError, KeyError, TypeError) as error:
                print(f'container {self.name}: bad request {line[:200]!r}: {error}', file=sys.stderr,
                      flush=True)
        self.quit_all()

    def wait_all(self, timeout: float) -> bool:
        """Wait for every module thread to end; whether they did within ``timeout``."""
        deadline = time.monotonic() + timeout
        while True:
            with self._lock:
                threads = [thread for _, thread in self.modules.values()]
            if not threads:
                if self.hub is not None and self._hub_thread is not None:
                    self.hub.stop()
                    self._hub_thread.join(max(0.0, deadline - time.monotonic()))
                return True
            left = deadline - time.monotonic()
            if left <= 0:
                return False
            if threads[0] is None:
                time.sleep(min(left, 0.05))             # a task: its end is polled
            else:
                threads[0].join(min(left, 0.2))


def _exit_code(value: object) -> int:
    if value is None:
        return 0
    if isinstance(value, int):
        return value
    print(value, file=sys.stderr)
    return 1


def main(argv: list[str] | None = None) -> int:
    """``container -n NAME --control FD [--ros-args ...]``: serve until the MCP's line closes or a
    SIGINT/SIGTERM comes, then quit every module and end."""
    argv = list(sys.argv if argv is None else argv)
    ros_arguments: list[str] = []
    if '--ros-args' in argv:
        index = argv.index('--ros-args')
        argv, ros_arguments = argv[:index], argv[index:]
    parser = argparse.ArgumentParser(prog='container', description=__doc__.split('\n\n')[0])
    parser.add_argument('-n', '--name', required=True, help="the container's name in the MCP config")
    parser.add_argument('--control', type=int, required=True, help="the MCP's socket (an inherited fd)")
    parser.add_argument('--cooperative', action='store_true',
                        help='the modules take turns in one thread (wurde_core.cooperative)')
    parser.add_argument('--quantum', type=float, default=cooperative.QUANTUM_S,
                        help="with --cooperative: the hub's least time between wake-ups for deadlines (s)")
    args = parser.parse_args(argv[1:])
    serialize_imports()
    host = Host(args.name, socket.socket(fileno=args.control), ros_arguments,
                quantum=args.quantum if args.cooperative else None)

    def on_signal(_signum: int, _frame: Any) -> None:
        host.quit_all()
        try:
            host.control.shutdown(socket.SHUT_RD)   # ends serve()'s read
        except OSError:
            pass
    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)
    host.serve()
    ended = host.wait_all(QUIT_WAIT_S)
    host.context.try_shutdown()
    skip_final_collection()     # the last collection walked every module's objects: 0.15 s of CPU
    return 0 if ended else 1


if __name__ == '__main__':
    sys.exit(main())
