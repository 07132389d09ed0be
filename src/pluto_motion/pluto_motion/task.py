"""A running task's handle, in the manner of nav2_simple_commander (``isTaskComplete``,
``getResult``, ``cancelTask``): a proxy's ``go_to`` returns a :class:`Task` that the caller polls.

The handle knows nothing of a particular module: it is made from two callables, ``poll`` (run the
program's loop once and say whether the task has ended, how and why) and ``cancel`` (tell the module to
stop the task).  The AvoidProxy makes one for the avoid goto; a MotionProxy can make one for moveto.
"""

from __future__ import annotations

import enum
import time
from collections.abc import Callable

__all__ = ['Task', 'TaskResult']

#: Pause between two polls of :meth:`Task.wait` (s).
POLL_S = 0.01


class TaskResult(enum.Enum):
    """How a task ended; UNKNOWN while it runs (nav2's TaskResult)."""

    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


class Task:
    """One task.  :meth:`is_task_complete` runs the program's loop once per call (so a polling loop
    needs no other spinning), :meth:`result` says how it ended, :meth:`cancel` ends it."""

    def __init__(self, poll: Callable[[], tuple[TaskResult, str]], cancel: Callable[[], object], *,
                 timeout: float | None = None) -> None:
        """:param poll: one turn of the loop; the result so far (UNKNOWN while running) and why
            (a reason for FAILED, else anything).
        :param cancel: stop the task in the module.
        :param timeout: seconds after which the task counts as FAILED (None: never)."""
        self._poll = poll
        self._cancel = cancel
        self._deadline = None if timeout is None else time.monotonic() + timeout
        self._result = TaskResult.UNKNOWN
        #: Why it failed, when it did (for the caller's log).
        self.reason = ''

    def is_task_complete(self) -> bool:
        """Whether the task has ended (runs the loop once while it has not)."""
        if self._result is TaskResult.UNKNOWN:
            self._result, self.reason = self._poll()
            if self._result is TaskResult.UNKNOWN and self._deadline is not None \
                    and time.monotonic() > self._deadline:
                self._cancel()
                self._result, self.reason = TaskResult.FAILED, 'timed out'
        return self._result is not TaskResult.UNKNOWN

    def result(self) -> TaskResult:
        """SUCCEEDED, CANCELED or FAILED once complete; UNKNOWN while running."""
        return self._result

    def cancel(self) -> None:
        """Stop the task; its result becomes CANCELED (an ended task keeps its result)."""
        if self._result is TaskResult.UNKNOWN:
            self._cancel()
            self._result = TaskResult.CANCELED

    def wait(self, timeout: float) -> TaskResult:
        """Poll until complete or ``timeout`` s; the result (UNKNOWN if still running).

        :param timeout: the longest wait (s).
        """
        deadline = time.monotonic() + timeout
        while not self.is_task_complete() and time.monotonic() < deadline:
            time.sleep(POLL_S)      # a poll that does not spin (``spin=False``) must not take a core
        return self._result
