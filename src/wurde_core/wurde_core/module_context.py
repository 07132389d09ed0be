"""What a module owns when several modules share one process (a container, issue 39).

A module is normally a process: the MCP hands it its settings in the environment
(:mod:`wurde_core.heartbeat`, :mod:`wurde_core.resume`), it has one global role configuration and
logger, one rclpy context (one DDS participant), and its signal handlers.  In a container
(:mod:`wurde_mcp.container`) each module runs in a thread of its own, or as a task of a
cooperative container's hub thread (:mod:`wurde_core.cooperative`), and what would be
process-wide is the module's: the container enters a :class:`ModuleContext` in the module's
thread or task, and the readers below look there first.  A module outside a container has none, and
nothing changes for it.
"""

from __future__ import annotations

import contextvars
import os
import threading
from dataclasses import dataclass, field
from typing import Any


@dataclass
class ModuleContext:
    """One contained module's share of the process."""

    #: The module's name in the MCP configuration.
    name: str
    #: The variables the MCP would have put in a process's environment for it (read before the
    #: process's own environment).
    environment: dict[str, str] = field(default_factory=dict)
    #: The container's rclpy context: every contained node lives in it (one DDS participant).
    rclpy_context: Any = None
    #: Process-wide singletons made per module (the role configuration, the logger), by key.
    singletons: dict[str, Any] = field(default_factory=dict)
    #: The module's CommsManager once it has one (the container's way to tell it to quit).
    manager: Any = None
    #: A quit asked for before the module made its CommsManager.
    quit_requested: bool = False
    #: The module thread's kernel id: the "pid" its heartbeat reports, unique per start.
    thread_id: int = 0
    lock: threading.Lock = field(default_factory=threading.Lock)

    def request_quit(self) -> None:
        """Tell the module to quit, as SIGINT or SIGTERM tells a module process."""
        with self.lock:
            self.quit_requested = True
            manager = self.manager
        if manager is not None:
            manager.request_quit()


#: The module running: a context variable, so that it is per thread and, in a cooperative
#: container, per greenlet (:mod:`wurde_core.cooperative`; both start without one).
_current: contextvars.ContextVar[ModuleContext | None] = contextvars.ContextVar(
    'wurde_module_context', default=None)


def current() -> ModuleContext | None:
    """The context of the module running in this thread, or None outside a container."""
    return _current.get()


def enter(context: ModuleContext, identity: int | None = None) -> None:
    """Make ``context`` this thread's (the container, at the start of a module's thread).

    :param context: the module's context; its :attr:`~ModuleContext.thread_id` is set here.
    :param identity: what the module reports as its pid; None: the thread's kernel id.
    """
    context.thread_id = threading.get_native_id() if identity is None else identity
    _current.set(context)


def leave() -> None:
    """This thread runs no module any more."""
    _current.set(None)


def getenv(key: str, default: str = '') -> str:
    """``key`` from the module's environment: its context's, else the process's.

    :param key: the variable's name.
    :param default: what a variable set in neither gives.
    """
    context = current()
    if context is not None and key in context.environment:
        return context.environment[key]
    return os.environ.get(key, default)


def process_id() -> int:
    """What the module reports as its process id: the thread's id in a container (the kernel
    knows it as a task: ``/proc/<id>`` shows its CPU time), else the process's."""
    context = current()
    return context.thread_id if context is not None else os.getpid()


def singleton(key: str, default: Any) -> Any:
    """The module's ``key`` singleton in a container (None where none was set), or ``default``
    outside one.

    :param key: the singleton's name (``'configuration'``, ``'logger'``).
    :param default: the caller's process-wide value, returned outside a container.
    """
    context = current()
    if context is None:
        return default
    return context.singletons.get(key)


def set_singleton(key: str, value: Any) -> bool:
    """Keep ``value`` as the module's ``key`` singleton; False outside a container (the caller
    keeps it process-wide).

    :param key: the singleton's name.
    :param value: the module's own value.
    """
    context = current()
    if context is None:
        return False
    context.singletons[key] = value
    return True
