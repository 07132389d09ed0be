"""``replay``: put the messages of a rosbag2 bag back on their topics with the original timing.

    replay BAG [-r RATE] [-t REGEX] [-w SECONDS] [-n NODE ...]

Mobotware's replay for this suite.  BAG is a bag directory (``metadata.yaml``; split files in
order; zstd file or message compression; MCAP or sqlite3 storage), its ``metadata.yaml``, or one
``.mcap`` or ``.db3`` file (:mod:`.bag_reader`): what :mod:`.record` and ``ros2 bag record`` write.
The CDR bytes stored are published as they are (raw), each topic with the QoS its publishers
offered when recorded (:func:`.qos.replay_qos`: ``/tf_static`` and ``/map`` transient local), at
the recorded pace times ``-r`` (2: twice as fast; 0: as fast as possible), so that localization can
be run again on a recorded run with the simulator off.  Before the first message it waits, at most
``-w`` seconds (default 10), until every topic it will publish has a subscriber and every
subscriber the ROS graph knows of is matched, and until each node named by ``-n`` (``/ns/name`` or
``name``) reads one of its topics: a message published before discovery would reach nobody, and
with two readers of a topic, the first one matched is not enough.  Topics matching ``-t`` only
(default all).

A topic whose message type is not installed here is skipped with a warning naming topic and type;
a serialization format other than CDR is refused (exit status 1) naming format and topics (leave
them out with ``-t``); so is a bag that cannot be read, with the file and the reason.  Prints
``replay: N topics from BAG`` before the first message and ``replay: N messages`` at the end;
SIGINT or SIGTERM stop it early (exit status 0).
"""

from __future__ import annotations

import argparse
import pathlib
import re
import signal
import sys
import time
from collections.abc import Iterable
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node, NodeNameNonExistentError
from rclpy.signals import SignalHandlerOptions

from .bag_reader import Bag, BagTopic, open_bag
from .errors import BagError, MessageTypeError
from .message_types import message_class
from .qos import replay_qos

__all__ = ['main']

#: The only serialization format replayed (what rmw publishes raw).
CDR = 'cdr'


def _warn(text: str) -> None:
    print(f'replay: {text}', file=sys.stderr, flush=True)


def _readers_ready(node: Node, publishers: Iterable[Any], nodes: list[str]) -> bool:
    """Every publisher matched to every subscriber the graph shows (and to one at least), and every
    node of ``nodes`` seen reading one of the topics."""
    publishers = list(publishers)
    topics = {p.topic_name for p in publishers}
    for name in nodes:
        namespace, _, base = name.rpartition('/')
        try:
            read = node.get_subscriber_names_and_types_by_node(base, namespace or '/')
        except NodeNameNonExistentError:
            return False
        if not topics & {topic for topic, _ in read}:
            return False
    return all(p.get_subscription_count() >= max(1, node.count_subscribers(p.topic_name))
               for p in publishers)


def _selected(bag: Bag, pattern: str) -> list[BagTopic]:
    """The topics matching ``pattern``.

    :raises BagError: one of them is not serialized as CDR (named with its format).
    """
    include = re.compile(pattern)
    topics = [t for t in bag.topics if include.search(t.name)]
    other: dict[str, list[str]] = {}
    for topic in topics:
        if topic.serialization_format.lower() != CDR:
            other.setdefault(topic.serialization_format, []).append(topic.name)
    if other:
        formats = '; '.join(f'{fmt!r} ({", ".join(names)})' for fmt, names in sorted(other.items()))
        raise BagError(f'{bag.path}: serialization format {formats} is not supported: only CDR can be '
                       'replayed (leave those topics out with -t)')
    return topics


def _publishers(node: Node, topics: list[BagTopic]) -> dict[BagTopic, Any]:
    """A publisher per topic whose type is installed; a warning for each that is skipped."""
    publishers = {}
    for topic in topics:
        try:
            cls = message_class(topic.type_name)
        except MessageTypeError as error:
            _warn(f'{topic.name}: skipped: {error}')
            continue
        try:
            publishers[topic] = node.create_publisher(cls, topic.name, replay_qos(topic.offers, topic.legacy))
        except Exception as error:  # noqa: BLE001 -- rclpy's errors for a name or type from the file
            _warn(f'{topic.name}: skipped: no publisher of {topic.type_name} can be made ({error})')
    return publishers


class _Stop:
    """Whether SIGINT or SIGTERM asked the replay to stop."""

    def __init__(self) -> None:
        self.asked = False
        signal.signal(signal.SIGINT, self._ask)
        signal.signal(signal.SIGTERM, self._ask)

    def _ask(self, _signum: int, _frame: Any) -> None:
        self.asked = True


def _play(bag: Bag, args: argparse.Namespace, stop: _Stop) -> int:
    """Publish the selected topics' messages; how many were published."""
    topics = _selected(bag, args.topics)
    for warning in bag.warnings:
        _warn(warning)
    context = Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('wurde_replay', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    count = 0
    try:
        publishers = _publishers(node, topics)
        deadline = time.monotonic() + args.wait
        while not stop.asked and not _readers_ready(node, publishers.values(), args.node) \
                and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
        skipped = len(topics) - len(publishers)
        print(f'replay: {len(publishers)} topics from {args.bag}' + (f' ({skipped} skipped)' if skipped else ''),
              flush=True)
        start, first = time.monotonic(), None
        for topic, stamp, data in bag.messages(publishers):
            if first is None:
                first = stamp
            if args.rate > 0:
                due = start + (stamp - first) / 1e9 / args.rate
                while (left := due - time.monotonic()) > 0 and not stop.asked:
                    executor.spin_once(timeout_sec=min(left, 0.05))
            if stop.asked:
                break
            publishers[topic].publish(data)
            count += 1
        # Reliable delivery of the last messages before the publishers go.
        end = time.monotonic() + 1.0
        while time.monotonic() < end and any(not p.wait_for_all_acked(Duration(seconds=0.1))
                                             for p in publishers.values()):
            executor.spin_once(timeout_sec=0.01)
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
    return count


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='replay', description=__doc__.splitlines()[0])
    parser.add_argument('bag', help='a bag directory, its metadata.yaml, or one .mcap or .db3 file')
    parser.add_argument('-r', '--rate', type=float, default=1.0, help='pace (2: twice as fast; 0: no waiting)')
    parser.add_argument('-t', '--topics', default='', help='replay topics matching this regex (default all)')
    parser.add_argument('-w', '--wait', type=float, default=10.0,
                        help='longest wait for every topic to have a subscriber (s)')
    parser.add_argument('-n', '--node', action='append', default=[],
                        help='wait until this node reads a replayed topic (repeatable)')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv[1:])
    try:
        re.compile(args.topics)
    except re.error as error:
        parser.error(f'-t {args.topics!r} is not a regular expression: {error}')
    stop = _Stop()
    try:
        with open_bag(pathlib.Path(args.bag)) as bag:
            count = _play(bag, args, stop)
    except BagError as error:
        _warn(str(error))
        return 1
    print(f'replay: {count} messages', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
