"""``record``: write ROS 2 topics to an MCAP file while the robot runs.

    record [-o FILE] [-t REGEX] [-x REGEX] [-n COUNT]

Every topic of the ROS graph whose name matches ``-t`` (default: all) and not ``-x`` (default:
``/rosout`` and ``/parameter_events``) is recorded — the WURDE streams (``/wurde/.../data``,
``info``, ``request``) and the standard topics (``/tf``, ``/scan``, ``/odom``, ...) alike.  The graph
is looked at every :data:`DISCOVER_S`, so topics that appear later are recorded from then on.  Each
message is stored as the CDR bytes that travelled (a raw subscription: nothing decoded or
re-encoded), on a channel with the type's full definition (:mod:`.schema`) and the publishers'
durability in its metadata (:mod:`.replay` offers it again).  A subscription is transient local
when every publisher is, so the latched info and ``/tf_static`` already sent are recorded too.

Ends on SIGINT or SIGTERM (or after ``-n`` messages), finishing the file so that it is complete;
prints ``record ready`` when listening and a line per topic added.
"""

from __future__ import annotations

import argparse
import importlib
import re
import signal
import sys
import time
from typing import Any

import rclpy
from mcap.writer import Writer
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions

from .schema import message_definition

__all__ = ['DISCOVER_S', 'Recorder', 'main', 'message_class']

#: How often the graph is looked at for new topics (s).
DISCOVER_S = 0.5
DEFAULT_EXCLUDE = r'^/(rosout|parameter_events)$'


def message_class(type_name: str) -> Any:
    """The Python class of ``pkg/msg/Name``."""
    package, _, name = type_name.split('/')
    return getattr(importlib.import_module(f'{package}.msg'), name)


class Recorder:
    """The topics matching ``include`` and not ``exclude``, written to ``writer`` as they arrive."""

    def __init__(self, node: Any, writer: Writer, include: str, exclude: str) -> None:
        self.node = node
        self.writer = writer
        self.include = re.compile(include)
        self.exclude = re.compile(exclude)
        self.channels: dict[str, int] = {}
        self.schemas: dict[str, int] = {}
        self.count = 0
        self._subscriptions: list[Any] = []

    def discover(self) -> list[str]:
        """Subscribe to the matching topics not yet recorded; the names added."""
        added = []
        for topic, types in self.node.get_topic_names_and_types():
            if topic in self.channels or len(types) != 1 or not self.include.search(topic) \
                    or self.exclude.search(topic):
                continue
            publishers = self.node.get_publishers_info_by_topic(topic)
            if not publishers:
                continue
            latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in publishers)
            reliable = all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in publishers)
            type_name = types[0]
            if type_name not in self.schemas:
                try:
                    definition = message_definition(type_name)
                except (OSError, ValueError) as exc:
                    print(f'record: {topic}: no definition of {type_name} ({exc}); not recorded',
                          file=sys.stderr, flush=True)
                    self.channels[topic] = -1
                    continue
                self.schemas[type_name] = self.writer.register_schema(type_name, 'ros2msg', definition.encode())
            durability = 'transient_local' if latched else 'volatile'
            channel = self.writer.register_channel(topic, 'cdr', self.schemas[type_name],
                                                   {'durability': durability,
                                                    'reliability': 'reliable' if reliable else 'best_effort'})
            self.channels[topic] = channel
            qos = QoSProfile(depth=1000,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
                             reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT)
            self._subscriptions.append(self.node.create_subscription(
                message_class(type_name), topic, lambda data, c=channel: self._write(c, data), qos, raw=True))
            added.append(topic)
        return added

    def _write(self, channel: int, data: bytes) -> None:
        now = time.time_ns()
        self.writer.add_message(channel, log_time=now, data=data, publish_time=now, sequence=self.count)
        self.count += 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='record', description=__doc__.splitlines()[0])
    parser.add_argument('-o', '--output', default='recording.mcap', help='the MCAP file (default recording.mcap)')
    parser.add_argument('-t', '--topics', default='', help='record topics matching this regex (default all)')
    parser.add_argument('-x', '--exclude', default=DEFAULT_EXCLUDE, help='leave out topics matching this regex')
    parser.add_argument('-n', '--count', type=int, default=0, help='stop after this many messages (0: never)')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv[1:])
    stop = {'now': False}

    def ask_stop(signum: int, frame: Any) -> None:
        stop['now'] = True

    signal.signal(signal.SIGINT, ask_stop)
    signal.signal(signal.SIGTERM, ask_stop)
    context = Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('wurde_record', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    with open(args.output, 'wb') as stream:
        writer = Writer(stream)
        writer.start(profile='ros2', library='wurde_mcp record')
        recorder = Recorder(node, writer, args.topics, args.exclude)
        print(f'record ready: writing {args.output}', flush=True)
        looked = -DISCOVER_S
        try:
            while not stop['now'] and not (args.count and recorder.count >= args.count):
                if time.monotonic() - looked >= DISCOVER_S:
                    looked = time.monotonic()
                    for topic in recorder.discover():
                        print(f'record: {topic}', flush=True)
                executor.spin_once(timeout_sec=0.05)
        finally:
            writer.finish()
            executor.shutdown()
            node.destroy_node()
            rclpy.shutdown(context=context)
    recorded = sum(1 for c in recorder.channels.values() if c >= 0)
    print(f'record: {recorder.count} messages on {recorded} topics in {args.output}', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
