"""``replay``: put the messages of an MCAP file back on their topics with the original timing.

    replay FILE [-r RATE] [-t REGEX] [-w SECONDS] [-n NODE ...]

Mobotware's replay for this suite: the CDR bytes :mod:`.record` stored are published as they are
(raw), each topic with the durability it was recorded with, at the recorded pace times ``-r``
(2: twice as fast; 0: as fast as possible), so that localization can be run again on a recorded run
with the simulator off.  Before the first message it waits, at most ``-w`` seconds (default 10),
until every topic it will publish has a subscriber and every subscriber the ROS graph knows of is
matched, and until each node named by ``-n`` (``/ns/name`` or ``name``) reads one of its topics: a
message published before discovery would reach nobody, and with two readers of a topic, the first
one matched is not enough.  Topics matching ``-t`` only (default all).  Prints ``replay: N messages``
at the end.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from collections.abc import Iterable
from typing import Any

import rclpy
from mcap.reader import make_reader
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node, NodeNameNonExistentError
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from .tap import message_class

__all__ = ['main']


def _qos(metadata: dict[str, str]) -> QoSProfile:
    return QoSProfile(depth=1000,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if metadata.get('durability') == 'transient_local'
                      else DurabilityPolicy.VOLATILE,
                      reliability=ReliabilityPolicy.BEST_EFFORT if metadata.get('reliability') == 'best_effort'
                      else ReliabilityPolicy.RELIABLE)


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='replay', description=__doc__.splitlines()[0])
    parser.add_argument('file', help='an MCAP file written by record (or rosbag2)')
    parser.add_argument('-r', '--rate', type=float, default=1.0, help='pace (2: twice as fast; 0: no waiting)')
    parser.add_argument('-t', '--topics', default='', help='replay topics matching this regex (default all)')
    parser.add_argument('-w', '--wait', type=float, default=10.0,
                        help='longest wait for every topic to have a subscriber (s)')
    parser.add_argument('-n', '--node', action='append', default=[],
                        help='wait until this node reads a replayed topic (repeatable)')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv[1:])
    include = re.compile(args.topics)
    context = Context()
    rclpy.init(context=context)
    node = rclpy.create_node('wurde_replay', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    publishers: dict[int, Any] = {}
    count = 0
    try:
        with open(args.file, 'rb') as stream:
            reader = make_reader(stream)
            summary = reader.get_summary()
            if summary is None:
                print(f'replay: {args.file} has no summary (not finished?)', file=sys.stderr, flush=True)
                return 1
            for channel_id, channel in summary.channels.items():
                schema = summary.schemas.get(channel.schema_id)
                if schema is None or channel.message_encoding != 'cdr' or not include.search(channel.topic):
                    continue
                publishers[channel_id] = node.create_publisher(message_class(schema.name), channel.topic,
                                                               _qos(dict(channel.metadata)))
            deadline = time.monotonic() + args.wait
            while not _readers_ready(node, publishers.values(), args.node) and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.05)
            print(f'replay: {len(publishers)} topics from {args.file}', flush=True)
            start, first = time.monotonic(), None
            for _, channel, message in reader.iter_messages(log_time_order=True):
                publisher = publishers.get(channel.id)
                if publisher is None:
                    continue
                if first is None:
                    first = message.log_time
                if args.rate > 0:
                    due = start + (message.log_time - first) / 1e9 / args.rate
                    while (left := due - time.monotonic()) > 0:
                        executor.spin_once(timeout_sec=min(left, 0.05))
                publisher.publish(message.data)
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
    print(f'replay: {count} messages', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
