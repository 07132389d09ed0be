"""A WURDE module for the container tests (issue 39), run as ``counter_module:main``.

It counts: one more every step (0.1 s), supplied as Foo data on ``<name>_count`` (ranges[0] the
count).  The count is its
state across restarts: kept in the resume file the MCP gives it (:mod:`wurde_core.resume`) at every
step, and taken up again when the MCP restarts it, as the localModule takes up its pose.  ``-f
FILE``: when FILE appears, the module removes it and raises — its work ends in an exception.
"""

from __future__ import annotations

import os
import sys

from wurde_core import CommsManager, RunState
from wurde_core.interfaces import Foo
from wurde_core.resume import ResumeState


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('Counter')
    user = manager.parse_options(argv, 'f:').user
    manager.set_sleep(0.1)
    state = ResumeState(every_s=0.0)
    saved, why = state.load()
    count = int(saved['count']) if saved else 0
    print(f'{manager.name}: count from {count} ({why})', flush=True)
    out = Foo(f'{manager.name}_count')
    manager.register_supplier(out)
    fail = user.get('f')
    while manager.run_update() == RunState.RUN:
        count += 1
        state.save({'count': count})
        out.data.ranges = [float(count)]
        out.publish_data()
        if fail and os.path.exists(fail):
            os.remove(fail)
            raise RuntimeError(f'{manager.name}: told to fail at count {count}')
    manager.clean_up(exiting=True)
    return 0
