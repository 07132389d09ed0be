#!/usr/bin/env python3
"""A WURDE module for MCP tests: supplies Foo on ``<name>_out``; ``-t TTL`` overrides its TTL."""

import sys

from wurde_core import CommsManager, RunState, global_configuration
from wurde_core.interfaces import Foo

manager = CommsManager('Worker')
manager.parse_options(sys.argv, 't:')
manager.set_sleep(0.5)  # TTL 1 s: no false zombies on a loaded 2-core machine
if global_configuration().have_option('t'):
    manager.set_heartbeat_only(float(global_configuration().get_option('t')))
foo = Foo(f'{manager.name}_out')
manager.register_supplier(foo)
while True:
    state = manager.run_update()
    if state == RunState.QUIT:
        break
    if state in (RunState.RESET, RunState.RESTART):
        manager.set_run()
    foo.data.ranges = [1.0]
    foo.publish_data()
manager.clean_up()
