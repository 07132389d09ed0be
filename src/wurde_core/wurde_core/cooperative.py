"""Cooperative scheduling: several modules' loops taking turns in one thread (issue 39).

A cooperative container (:mod:`wurde_mcp.container`, ``<container scheduling="cooperative">``)
runs each module's ``main`` in a greenlet of one :class:`Hub` thread instead of a thread of its
own.  A module gives up its turn only where a WURDE module waits anyway: the CommsManager's sleep
between loops (:func:`sleep`), its wait for data or a trigger (:func:`wait`), and ``time.sleep``
(:func:`patch_time_sleep`).  The hub sleeps until the earliest of its modules' deadlines, or until
one's subscriptions hold something, and then runs every module that is due, one after the other.

Why: on a virtual machine every wake-up of a thread from sleep runs cold (caches filled by the
host's other work while it slept).  A publish costs 7 µs warm and 140 µs as the first thing a
thread does after a 5 ms sleep; ten loops of a publish each cost 100 µs a pass as ten threads and
45 µs as one thread running them back to back (docs/benchmarks.md, "Cooperative containers").  The
hub wakes at most once per :data:`QUANTUM_S` for deadlines, so loops whose deadlines fall within
it run as one batch: a module sleeps its set time and at most one quantum more — WURDE's rate
control is "loose" (guide 5.2.2: it sleeps a set time, not accounting for the loop's work).

What it costs: a module that computes for long (a planner) holds every other module of the hub
until it waits again, where threads would have been switched every 5 ms; the trade-off is the
user's choice of scheduling, per container (docs/mcp.md, "Containers").
"""

from __future__ import annotations

import collections
import contextvars
import math
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any


__all__ = ['QUANTUM_S', 'Hub', 'Task', 'current_task', 'patch_time_sleep', 'sleep', 'wait']

#: The hub wakes for deadlines at most once per quantum (s): deadlines within it run as one batch.
#: 20 ms, the simulator's step: config/pluto's whole robot took 27-35 % of one core with it,
#: 28-42 % with 5 ms and 35-44 % as threads (docs/benchmarks.md).
QUANTUM_S = 0.02
#: ``time.sleep`` as the interpreter had it (a task's sleep yields; the hub's own waits do not).
_real_sleep = time.sleep
_task: contextvars.ContextVar[Task | None] = contextvars.ContextVar('wurde_cooperative_task', default=None)


class Task:
    """One module's loop in a :class:`Hub`: its greenlet and what it waits for."""

    def __init__(self, hub: Hub, name: str, function: Callable[..., Any], args: tuple[Any, ...]) -> None:
        """A task of ``hub`` that will run ``function(*args)``.

        :param hub: the hub it runs in.
        :param name: its name (the module's).
        :param function: its work; its end is the task's.
        :param args: the work's arguments.
        """
        self.hub = hub
        self.name = name
        self._function = function
        self._args = args
        import greenlet         # only cooperative containers need it
        self.greenlet = greenlet.greenlet(self._body, parent=hub.greenlet)
        #: When the task is to run again (monotonic s); None: not before its data or a wake.
        self.deadline: float | None = 0.0
        #: The :class:`~wurde_core.ros_adaptor.SubscriptionWaiter` whose entities wake the task.
        self.waiter: Any = None
        #: Whether the task's waiter held something when it was woken.
        self.arrived = False
        self.ended = False
        #: CPU seconds of the hub's thread spent in this task.
        self.cpu_s = 0.0

    def _body(self) -> None:
        _task.set(self)
        try:
            self._function(*self._args)
        finally:
            self.ended = True

    def block(self, seconds: float, waiter: Any = None) -> bool:
        """Give up the turn for at most ``seconds`` (or until ``waiter`` holds something).

        :param seconds: the longest time before the task runs again (inf: no limit).
        :param waiter: a :class:`~wurde_core.ros_adaptor.SubscriptionWaiter` whose data wake the
            task sooner; None: only the time.
        :returns: whether the waiter's data woke the task.
        """
        self.deadline = time.monotonic() + max(0.0, seconds) if math.isfinite(seconds) else None
        self.waiter = waiter
        self.arrived = False
        self.hub.greenlet.switch()
        return self.arrived


class Hub:
    """Runs :class:`Task` greenlets in the thread that calls :meth:`run`."""

    def __init__(self, group: Any, quantum_s: float = QUANTUM_S) -> None:
        """:param group: the :class:`~wurde_core.ros_adaptor.WaiterGroup` of the rclpy context
            whose subscriptions the tasks wait on (given, so that this module imports no adaptor).
        :param quantum_s: the least time between two wake-ups for deadlines."""
        self.context = group.context
        self.quantum_s = quantum_s
        self.tasks: list[Task] = []
        self.greenlet: Any = None
        self._calls: collections.deque[tuple[Callable[..., Any], tuple[Any, ...]]] = collections.deque()
        self._group = group
        self._stop = threading.Event()
        self.thread_id = 0

    def call_soon(self, function: Callable[..., Any], *args: Any) -> None:
        """Run ``function(*args)`` in the hub's thread at its next turn (from any thread).

        :param function: what to run.
        :param args: its arguments.
        """
        self._calls.append((function, args))
        self._group.trigger()

    def spawn(self, name: str, function: Callable[..., Any], *args: Any) -> Task:
        """A task running ``function(*args)``, first at the hub's next turn (the hub's thread).

        :param name: the task's name.
        :param function: its work.
        :param args: the work's arguments.
        """
        task = Task(self, name, function, args)
        self.tasks.append(task)
        return task

    def stop(self) -> None:
        """End :meth:`run` once no task is left (from any thread)."""
        self._stop.set()
        self._group.trigger()

    def run(self) -> None:
        """Run the tasks until :meth:`stop` and none is left."""
        import greenlet
        self.greenlet = greenlet.getcurrent()
        self.thread_id = threading.get_native_id()
        for task in self.tasks:
            task.greenlet.parent = self.greenlet
        last_batch = -math.inf
        while True:
            while self._calls:
                function, args = self._calls.popleft()
                function(*args)
            if self._stop.is_set() and not self.tasks:
                return
            now = time.monotonic()
            due = [t for t in self.tasks if t.deadline is not None and t.deadline <= now]
            if due:
                last_batch = now
                self._run_batch(due)
                if self._stop.is_set() and not self.tasks:
                    return
            deadlines = [t.deadline for t in self.tasks if t.deadline is not None]
            timeout = -1.0
            if deadlines:
                timeout = max(min(deadlines), last_batch + self.quantum_s) - time.monotonic()
            for task in self._arrived(max(0.0, timeout) if deadlines else -1.0):
                task.deadline = 0.0          # runs in the next batch

    def _run_batch(self, due: list[Task]) -> None:
        for task in due:
            if task.ended:
                continue
            before = time.thread_time()
            try:
                task.greenlet.switch()
            except BaseException:   # noqa: BLE001 - a task's end is its own, never the hub's
                traceback.print_exc()
                task.ended = True
            task.cpu_s += time.thread_time() - before
            if task.ended or task.greenlet.dead:
                task.ended = True
                self.tasks.remove(task)

    def _arrived(self, timeout: float) -> list[Task]:
        """Wait at most ``timeout`` s (< 0: without limit) for a waiting task's data or a call;
        the tasks whose waiter holds something, marked ``arrived``."""
        waiting = [t for t in self.tasks if t.waiter is not None]
        found = [waiting[i] for i in self._group.wait([t.waiter for t in waiting], timeout)]
        for task in found:
            task.arrived = True
        return found


def current_task() -> Task | None:
    """The task running now, or None outside a hub (a thread or a process of its own)."""
    return _task.get()


def sleep(seconds: float) -> None:
    """``time.sleep`` that gives up a task's turn for ``seconds`` (a plain sleep outside a hub).

    :param seconds: how long.
    """
    task = _task.get()
    if task is None:
        _real_sleep(seconds)
    else:
        task.block(seconds)


def wait(waiter: Any, seconds: float) -> bool | None:
    """In a task: give up the turn until ``waiter``'s subscriptions hold something or ``seconds``
    pass, and say whether they do; outside a hub: None (the caller waits itself).

    :param waiter: the :class:`~wurde_core.ros_adaptor.SubscriptionWaiter` waited on.
    :param seconds: the longest wait.
    """
    task = _task.get()
    if task is None:
        return None
    return task.block(seconds, waiter)


def patch_time_sleep() -> None:
    """Make ``time.sleep`` :func:`sleep` in this process (a container's): a module that sleeps in
    its own code gives up its turn instead of holding the hub."""
    time.sleep = sleep  # type: ignore[assignment]  # takes the floats time.sleep is given
