#!/usr/bin/env python3
"""The soak's numbered stream: a module that supplies Foo on ``SoakCount`` in queue mode.

Every message carries the supplier's sequence number (``header.sequence``, counted by its
outbox from 1 per process), so a queue-mode consumer can tell a message lost while both ends
were up (a gap inside one process's numbers) from the supplier's own death (the numbers start
again at 1).  It waits for its consumer to be matched before it sends the first one, so that a
new process's first messages are not sent into a subscription that is not there yet.

    soak_counter [-n NAME] [-s STREAM] [-f HZ]
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, global_configuration
from wurde_core.interfaces import Foo
from wurde_core.module_loop import run_loop, set_loop

#: Longest wait for the consumer at start (s); the soak's consumer is up long before.
PEERS_S = 30.0


def main(argv: list[str]) -> int:
    manager = CommsManager('SoakCounter')
    manager.parse_options(argv, 's:f:')
    config = global_configuration()
    stream = config.get_option('s') if config.have_option('s') else 'SoakCount'
    rate = float(config.get_option('f')) if config.have_option('f') else 20.0
    set_loop(manager, 1.0 / rate)
    count = Foo(stream)
    count.set_queue_mode(True)
    manager.register_supplier(count)
    count.wait_for_peers(PEERS_S)

    def step() -> None:
        count.data.ranges = [1.0]
        count.publish_data()

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
