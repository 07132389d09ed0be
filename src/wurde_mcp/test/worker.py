#!/usr/bin/env python3
"""A WURDE module for MCP tests: supplies Foo on ``<name>_out``.

``-t TTL`` overrides its TTL; ``-s`` makes it stubborn: it ignores Quit, SIGINT and SIGTERM, so
only SIGKILL ends it (the whole stop escalation runs).
"""

import signal
import sys

from wurde_core import CommsManager, RunState, global_configuration
from wurde_core.interfaces import Foo

manager = CommsManager('Worker')
manager.parse_options(sys.argv, 't:s')
manager.set_sleep(0.5)  # TTL 1 s: no false zombies on a loaded 2-core machine
config = global_configuration()
if config.have_option('t'):
    manager.set_heartbeat_only(float(config.get_option('t')))
stubborn = config.have_option('s') and not manager.options.registration
foo = Foo(f'{manager.name}_out')
manager.register_supplier(foo)


def _ignore(signum: int, _frame: object) -> None:
    print(f'stubborn: ignoring {signal.Signals(signum).name}', flush=True)


if stubborn:
    signal.signal(signal.SIGINT, _ignore)
    signal.signal(signal.SIGTERM, _ignore)
while True:
    state = manager.run_update()
    if state == RunState.QUIT and not stubborn:
        break
    if state != RunState.RUN and state != RunState.IDLE:
        manager.set_run()
    foo.data.ranges = [1.0]
    foo.publish_data()
manager.clean_up()
