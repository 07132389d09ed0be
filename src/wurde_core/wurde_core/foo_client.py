"""FooClient: the guide's client for FooServer (1.1.2), as written there, in Python."""

import sys

from wurde_core import CommsManager, Logger, RunState
from wurde_core.interfaces import Foo


def main() -> int:
    manager = CommsManager("FooClient")
    logger = Logger("FooClient")
    foo = Foo("Bar")
    manager.parse_options(sys.argv)
    foo.set_queue_mode(True)
    manager.register_supplier(logger)
    manager.register_consumer(foo)
    while manager.run_update() == RunState.RUN:
        while foo.new_info():
            foo.get_next_info()
            print(f'Info: MaxRange {foo.info.max_range.get_value()} '
                  f'angleMin {foo.info.angle_min.get_value()} '
                  f'angleMax {foo.info.angle_max.get_value()}', flush=True)
        while foo.new_data():
            foo.get_next_data()
            if len(foo.data.ranges) > 0:
                print(f'Timestamp: {foo.data.timestamp.get_seconds():.6f} '
                      f'Val {foo.data.ranges[0]}', flush=True)
    manager.clean_up()
    return 0


if __name__ == '__main__':
    sys.exit(main())
