"""``record``: write ROS 2 topics to an MCAP file while the robot runs.

    record [-o FILE] [-t REGEX] [-x REGEX] [-n COUNT]

Every topic of the ROS graph whose name matches ``-t`` (default: all) and not ``-x`` (default:
``/rosout`` and ``/parameter_events``) is recorded — the WURDE streams (``/wurde/.../data``,
``info``, ``request``) and the standard topics (``/tf``, ``/scan``, ``/odom``, ...) alike.  The graph
is looked at every :data:`.tap.DISCOVER_S`, so topics that appear later are recorded from then on.  Each
message is stored as the CDR bytes that travelled (a raw subscription: nothing decoded or
re-encoded), on a channel with the type's full definition (:mod:`.schema`) and the publishers'
durability in its metadata (:mod:`.replay` offers it again).  A subscription is transient local
when every publisher is, so the latched info and ``/tf_static`` already sent are recorded too.

Ends on SIGINT or SIGTERM (or after ``-n`` messages), finishing the file so that it is complete;
prints ``record ready`` when listening and a line per topic added.
"""

from __future__ import annotations

import argparse
import sys
import time

from mcap.writer import Writer

from .tap import DEFAULT_EXCLUDE, TopicTap, run_tap, tap_node

__all__ = ['McapSink', 'main']


class McapSink:
    """The MCAP file a :class:`~.tap.TopicTap` writes: a schema per type, a channel per topic."""

    def __init__(self, writer: Writer) -> None:
        self.writer = writer
        self.schemas: dict[str, int] = {}
        self.count = 0

    def open_channel(self, topic: str, type_name: str, definition: str, metadata: dict[str, str]) -> int:
        if type_name not in self.schemas:
            self.schemas[type_name] = self.writer.register_schema(type_name, 'ros2msg', definition.encode())
        return self.writer.register_channel(topic, 'cdr', self.schemas[type_name], metadata)

    def write(self, channel: int, data: bytes) -> None:
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
    with tap_node('wurde_record') as (node, executor, stopped), open(args.output, 'wb') as stream:
        writer = Writer(stream)
        writer.start(profile='ros2', library='wurde_mcp record')
        sink = McapSink(writer)
        recorder = TopicTap(node, args.topics, args.exclude, sink.open_channel, sink.write, 'record')
        print(f'record ready: writing {args.output}', flush=True)
        try:
            run_tap(recorder, executor,
                    lambda: stopped() or bool(args.count and recorder.count >= args.count))
        finally:
            writer.finish()
    recorded = sum(1 for c in recorder.channels.values() if c is not None)
    print(f'record: {recorder.count} messages on {recorded} topics in {args.output}', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
