"""``record``: write ROS 2 topics to a rosbag2 bag while the robot runs.

    record [-o NAME] [-t REGEX] [-x REGEX] [-n COUNT] [-b BYTES] [-d SECONDS]

Every topic of the ROS graph whose name matches ``-t`` (default: all) and not ``-x`` (default:
``/rosout`` and ``/parameter_events``) is recorded — the WURDE streams (``/wurde/.../data``,
``info``, ``request``) and the standard topics (``/tf``, ``/scan``, ``/odom``, ...) alike.  The graph
is looked at every :data:`.tap.DISCOVER_S`, so topics that appear later are recorded from then on.  Each
message is stored as the CDR bytes that travelled (a raw subscription: nothing decoded or
re-encoded), on a channel with the type's full definition (:mod:`.schema`), and with rosbag2's
``offered_qos_profiles`` (every publisher's QoS, which ``ros2 bag play`` and :mod:`.replay` offer
again: ``/tf_static`` and ``/map`` come back transient local) and ``topic_type_hash``.  A
subscription is transient local when every publisher is, so the latched info and ``/tf_static``
already sent are recorded too.

The output is chosen by its name (:mod:`.bag_writer`): ``-o NAME.mcap`` is one MCAP file (default
``recording.mcap``); any other name is a rosbag2 bag directory, made new, with ``NAME_0.mcap`` ...
and ``metadata.yaml`` (what ``ros2 bag record -o NAME`` writes; ``-b`` / ``-d`` start a new file
when the messages in the current one reach BYTES or span SECONDS).

Ends on SIGINT or SIGTERM (or after ``-n`` messages), finishing the output so that it is complete;
prints ``record ready`` when listening and a line per topic added.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
from typing import Any

from mcap.writer import Writer

from .bag_writer import BagDirectorySink, McapSink, single_file_metadata
from .errors import BagError
from .tap import DEFAULT_EXCLUDE, TopicTap, run_tap, tap_node

__all__ = ['McapSink', 'main']


def _arguments(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog='record', description=__doc__.splitlines()[0])
    parser.add_argument('-o', '--output', default='recording.mcap',
                        help='NAME.mcap: one MCAP file; any other name: a bag directory (default recording.mcap)')
    parser.add_argument('-t', '--topics', default='', help='record topics matching this regex (default all)')
    parser.add_argument('-x', '--exclude', default=DEFAULT_EXCLUDE, help='leave out topics matching this regex')
    parser.add_argument('-n', '--count', type=int, default=0, help='stop after this many messages (0: never)')
    parser.add_argument('-b', '--max-bag-size', type=int, default=0,
                        help='bag directory: a new file when its messages reach this many bytes (0: never)')
    parser.add_argument('-d', '--max-bag-duration', type=float, default=0.0,
                        help='bag directory: a new file when its messages span this many seconds (0: never)')
    args = parser.parse_args(argv)
    if args.output.endswith('.mcap') and (args.max_bag_size or args.max_bag_duration):
        parser.error('-b and -d split a bag directory: give -o a name without .mcap')
    if args.max_bag_size < 0 or args.max_bag_duration < 0:
        parser.error('-b and -d take 0 (no limit) or more')
    return args


def _tap(args: argparse.Namespace, open_channel: Any, write: Any, what: str) -> TopicTap:
    """Record every matching topic through ``open_channel`` and ``write`` until SIGINT, SIGTERM
    or ``-n`` messages; the tap, for its counts."""
    with tap_node('wurde_record') as (node, executor, stopped):
        recorder = TopicTap(node, args.topics, args.exclude, open_channel, write, 'record')
        print(f'record ready: writing {what}', flush=True)
        run_tap(recorder, executor, lambda: stopped() or bool(args.count and recorder.count >= args.count))
    return recorder


def _record_file(args: argparse.Namespace) -> str:
    """Record into one MCAP file; the summary line's end."""
    with open(args.output, 'wb') as stream:
        writer = Writer(stream)
        writer.start(profile='ros2', library='wurde_mcp record')
        sink = McapSink(writer, pathlib.Path(args.output).name)
        try:
            recorder = _tap(args, sink.open_channel, sink.write, args.output)
        finally:
            sink.finish(single_file_metadata(sink))
    recorded = sum(1 for c in recorder.channels.values() if c is not None)
    return f'{recorder.count} messages on {recorded} topics in {args.output}'


def _record_directory(args: argparse.Namespace) -> str:
    """Record into a new bag directory; the summary line's end."""
    bag = BagDirectorySink(pathlib.Path(args.output), max_bytes=args.max_bag_size,
                           max_seconds=args.max_bag_duration)
    bag.open()
    try:
        recorder = _tap(args, bag.open_channel, bag.write, f'the bag directory {args.output}')
    finally:
        bag.close()
    return f'{recorder.count} messages on {len(bag.topics)} topics in {args.output} ({len(bag.files)} files)'


def main(argv: list[str] | None = None) -> int:
    args = _arguments(sys.argv[1:] if argv is None else argv[1:])
    try:
        summary = _record_file(args) if args.output.endswith('.mcap') else _record_directory(args)
    except BagError as error:
        print(f'record: {error}', file=sys.stderr, flush=True)
        return 1
    except OSError as error:
        print(f'record: cannot write {args.output}: {error.strerror or error}', file=sys.stderr, flush=True)
        return 1
    print(f'record: {summary}', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
