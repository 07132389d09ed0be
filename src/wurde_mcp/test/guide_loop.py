#!/usr/bin/env python3
"""A WURDE module for MCP tests whose main loop is the guide's (5.2.1): it prints every run state
``run_update`` returns (``<name>: state IDLE``) and answers Reset with ``set_run``.

``-s`` asks for the states (``set_return_states``); ``-t TTL`` announces that TTL and ``-T`` asks
the MCP to trust it (``set_heartbeat_only(ttl, trust=True)``); ``-b S`` makes every loop turn after
the first few stay away S seconds (a long computation: no heartbeat meanwhile); ``-q`` makes it
stop beating for good after its first few turns (hung, asleep).
"""

import sys
import time

from wurde_core import CommsManager, RunState, global_configuration
from wurde_core.interfaces import Foo

#: Quick turns (0.1 s each) before the long ones: the MCP hears the module describe itself and
#: beat first (test_guide_run_states.QUICK_TURNS).
QUICK_TURNS = 30

manager = CommsManager('GuideLoop')
manager.parse_options(sys.argv, 'st:Tb:q')
manager.set_sleep(0.1)
config = global_configuration()
if config.have_option('t'):
    manager.set_heartbeat_only(float(config.get_option('t')), trust=config.have_option('T'))
if config.have_option('s'):
    manager.set_return_states()
gap = float(config.get_option('b')) if config.have_option('b') else 0.0
foo = Foo(f'{manager.name}_out')
manager.register_supplier(foo)
last = None
turns = 0
while True:
    state = manager.run_update()
    if state == RunState.QUIT:
        break
    if state != last:
        print(f'{manager.name}: state {state.name}', flush=True)
        last = state
    if state == RunState.RESET:
        print(f'{manager.name}: reset handled', flush=True)
        manager.set_run()
    turns += 1
    if turns >= QUICK_TURNS and config.have_option('q') and not manager.options.registration:
        print(f'{manager.name}: hanging', flush=True)
        time.sleep(3600)
    if turns >= QUICK_TURNS and gap:
        print(f'{manager.name}: away {gap} s after turn {turns}', flush=True)
        time.sleep(gap)                         # asleep, no run_update: no heartbeat meanwhile
manager.clean_up()
