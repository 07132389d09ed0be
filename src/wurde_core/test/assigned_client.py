"""A module whose Foo consumer uses STRAT_ASSIGNED (guide 1.1.5): prints what it gets."""

import sys

from wurde_core import CommsManager, ConnectionStrategy, RunState
from wurde_core.interfaces import Foo

manager = CommsManager('AssignedClient')
manager.parse_options(sys.argv[:1])
manager.set_sleep(0.01)
strategy = ConnectionStrategy[sys.argv[1]] if len(sys.argv) > 1 else ConnectionStrategy.ASSIGNED
foo = Foo(strategy, 'BarClient')
manager.register_consumer(foo)
announced = False
while manager.run_update() == RunState.RUN:
    if foo.is_connected() and not announced:
        print(f'CONNECTED {foo.stream}', flush=True)
        announced = True
    while foo.get_next_data():
        print(f'VALUE {foo.data.ranges[0]}', flush=True)
manager.clean_up()
