"""Whether a silent module's process is still working: its scheduler state and CPU time.

A module silent past its TTL is a zombie (guide 5.2.1), but on a loaded machine a healthy module
can be silent that long because it is starved of CPU, not hung: killing it then does harm (a
simulated base restarted mid-run teleports the robot to its start).  The supervisor therefore
asks the process before it judges (:meth:`wurde_mcp.supervisor.Supervisor._check_ttl`): stopped
(SIGSTOP, a debugger) is hung at once; runnable, or using CPU, is working and gets more time up
to a hard limit; asleep with no CPU used for a while is hung.
"""

from __future__ import annotations

import os
import pathlib

__all__ = ['ProcessState', 'process_state', 'where_threads_wait']

_TICK_S = 1.0 / os.sysconf('SC_CLK_TCK')


class ProcessState:
    """One reading of /proc/<pid>/stat: the state letter and the CPU seconds used so far."""

    __slots__ = ('state', 'cpu_s')

    def __init__(self, state: str, cpu_s: float) -> None:
        self.state, self.cpu_s = state, cpu_s

    @property
    def stopped(self) -> bool:
        """Stopped by a signal or traced: it cannot beat until someone resumes it."""
        return self.state in ('T', 't')

    @property
    def runnable(self) -> bool:
        return self.state == 'R'


def process_state(pid: int) -> ProcessState | None:
    """The process's state, or None when there is no such process (or no /proc)."""
    try:
        text = pathlib.Path(f'/proc/{pid}/stat').read_text()
    except OSError:
        return None
    fields = text.rsplit(')', 1)[1].split()      # the command name may hold spaces and ')'
    return ProcessState(fields[0], (int(fields[11]) + int(fields[12])) * _TICK_S)


def where_threads_wait(pid: int) -> str:
    """Where a process's threads are, for the log of a zombie verdict: per thread its name, state
    letter and the innermost kernel function it waits in (``/proc/<pid>/task/*/stack``, readable by
    root; '?' otherwise), so that a module killed as hung says what it hung on.  '' when the
    process is gone."""
    threads = []
    try:
        tasks = sorted(pathlib.Path(f'/proc/{pid}/task').iterdir(), key=lambda t: int(t.name))
    except OSError:
        return ''
    for task in tasks:
        try:
            name = (task / 'comm').read_text().strip()
            state = (task / 'stat').read_text().rsplit(')', 1)[1].split()[0]
        except (OSError, IndexError):
            continue
        try:
            frame = (task / 'stack').read_text().split('\n', 1)[0].split()[-1].split('+')[0]
        except (OSError, IndexError):
            frame = '?'
        threads.append(f'{name} {state} {frame}')
    return '; '.join(threads)
