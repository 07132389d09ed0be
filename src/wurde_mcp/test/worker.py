#!/usr/bin/env python3
"""A WURDE module for MCP tests: supplies Foo on ``<name>_out``.

``-t TTL`` overrides its TTL; ``-s`` makes it stubborn: it ignores Quit, SIGINT and SIGTERM, so
only SIGKILL ends it (the whole stop escalation runs).  SIGUSR1 makes it spin on the CPU for
2.5 s without a heartbeat (a starved or busy module: working, but silent); SIGUSR2 makes it sleep
for a minute without one (hung, though not stopped).  It prints ``<name>: idle`` on entering Idle
and ``<name>: running again`` on returning to Run (its state hooks).  ``-w S`` makes it work S s
after Quit before it ends (printing ``saving`` and ``saved``, as a slamModule saving its map);
``-q S`` asks the MCP for S s to end after Quit (``CommsManager.set_quit_time``); ``-d S`` sleeps S s
before it makes its node, so that nothing of it is on the graph until then (a module slow to
start).
"""

import os
import signal
import sys
import time

from wurde_core import CommsManager, RunState, global_configuration
from wurde_core.heartbeat import restart_count
from wurde_core.resume import STATE_ENV
from wurde_core.interfaces import Foo

if '-d' in sys.argv[:-1] and '-r' not in sys.argv:  # before its node: nothing of it on the graph yet
    time.sleep(float(sys.argv[sys.argv.index('-d') + 1]))
manager = CommsManager('Worker')
manager.parse_options(sys.argv, 't:sw:q:d:')
manager.set_sleep(0.5)  # TTL 1 s: no false zombies on a loaded 2-core machine
config = global_configuration()
if config.have_option('t'):
    manager.set_heartbeat_only(float(config.get_option('t')))
if config.have_option('q'):
    manager.set_quit_time(float(config.get_option('q')))
stubborn = config.have_option('s') and not manager.options.registration
foo = Foo(f'{manager.name}_out')
manager.register_supplier(foo)
print(f'{manager.name}: start {restart_count()} under this MCP, state in {os.environ.get(STATE_ENV)}', flush=True)


def _ignore(signum: int, _frame: object) -> None:
    print(f'stubborn: ignoring {signal.Signals(signum).name}', flush=True)


def _spin(_signum: int, _frame: object) -> None:
    print('spinning', flush=True)
    end = time.monotonic() + 2.5
    while time.monotonic() < end:
        pass
    print('spun', flush=True)


def _hang(_signum: int, _frame: object) -> None:
    print('hanging', flush=True)
    time.sleep(60.0)


if stubborn:
    signal.signal(signal.SIGINT, _ignore)
    signal.signal(signal.SIGTERM, _ignore)
manager.on_state(RunState.IDLE, lambda: print(f'{manager.name}: idle', flush=True))
manager.on_state(RunState.RUN, lambda: print(f'{manager.name}: running again', flush=True))
signal.signal(signal.SIGUSR1, _spin)
signal.signal(signal.SIGUSR2, _hang)
while True:
    state = manager.run_update()
    if state == RunState.QUIT and not stubborn:
        break
    if state != RunState.RUN and state != RunState.IDLE:
        manager.set_run()
    foo.data.ranges = [1.0]
    foo.publish_data()
if config.have_option('w'):
    print('saving', flush=True)
    time.sleep(float(config.get_option('w')))   # the work owed before the exit
    print('saved', flush=True)
manager.clean_up()
