"""FooServer: the guide's first program (1.1.2), as written there, in Python."""

import math
import sys

from wurde_core import CommsManager, Logger, RunState
from wurde_core.interfaces import Foo


def main() -> int:
    manager = CommsManager("FooServer")
    logger = Logger("FooServer")
    foo = Foo("Bar")
    manager.parse_options(sys.argv)
    foo.set_queue_mode(True)
    manager.register_supplier(foo)
    manager.register_supplier(logger)
    manager.set_sleep(0.2)
    foo.info.max_range.set_value(8.0)
    foo.info.angle_min.set_value(0.0)
    foo.info.angle_max.set_value(math.pi)
    foo.publish_info()
    foo.data.ranges.append(1.0)
    i = 0
    while manager.run_update() == RunState.RUN:
        foo.data.ranges[0] = i
        foo.publish_data()
        i += 1
    manager.clean_up()
    return 0


if __name__ == '__main__':
    sys.exit(main())
