"""Raw subscriptions to every matching topic of the ROS graph, for a sink that stores or serves
the CDR bytes as they travelled: the MCAP recorder (:mod:`.record`) and the live view
(:mod:`.live_view`) differ only in their sink.

Each topic gets one subscription whose QoS matches its publishers (transient local when every
publisher is, so latched info and ``/tf_static`` already sent arrive too; reliable when every
publisher is), and one sink channel, opened with the type's full ``ros2msg`` definition
(:mod:`.schema`) and as metadata rosbag2's ``offered_qos_profiles`` (every publisher's profile,
:mod:`.qos`) and ``topic_type_hash``, and the ``durability`` and ``reliability`` the subscription
took (which the live view uses to resend latched messages).
"""

from __future__ import annotations

import contextlib
import re
import signal
import sys
import time
from collections.abc import Callable, Iterator
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from wurde_core import ros_adaptor

from .message_types import message_class
from .qos import offered_profile, offered_qos_yaml
from .schema import message_definition

__all__ = ['DEFAULT_EXCLUDE', 'DISCOVER_S', 'TopicTap', 'message_class', 'run_tap', 'tap_node']

DEFAULT_EXCLUDE = r'^/(rosout|parameter_events)$'
#: How often the graph is looked at for new topics (s).
DISCOVER_S = 0.5
#: Opens the sink's channel: (topic, type name, definition, metadata) -> the channel.
OpenChannel = Callable[[str, str, str, dict[str, str]], Any]
#: Takes one message: (channel, CDR bytes).
Write = Callable[[Any, bytes], None]


class TopicTap:
    """The topics matching ``include`` and not ``exclude``, handed to a sink as they arrive."""

    def __init__(self, node: Any, include: str, exclude: str, open_channel: OpenChannel,
                 write: Write, program: str) -> None:
        """``program`` names the tool in its messages."""
        self.node = node
        self.include = re.compile(include)
        self.exclude = re.compile(exclude)
        self.open_channel = open_channel
        self.write = write
        self.program = program
        #: The sink's channel of each topic taken (None: its type has no definition here).
        self.channels: dict[str, Any] = {}
        self.count = 0
        self._definitions: dict[str, str] = {}
        self._subscriptions: list[Any] = []
        #: Topics whose first message has come (a subscription is matched some time after it is made).
        self.flowing: set[str] = set()

    def discover(self) -> list[str]:
        """Subscribe to the matching topics not yet taken; the names added."""
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
            definition = self._definition(topic, type_name)
            if definition is None:
                self.channels[topic] = None
                continue
            channel = self.open_channel(topic, type_name, definition, {
                'offered_qos_profiles': offered_qos_yaml([offered_profile(p.qos_profile) for p in publishers]),
                'topic_type_hash': str(publishers[0].topic_type_hash),
                'durability': 'transient_local' if latched else 'volatile',
                'reliability': 'reliable' if reliable else 'best_effort'})
            self.channels[topic] = channel
            qos = QoSProfile(depth=1000,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
                             reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT)
            self._subscriptions.append(self.node.create_subscription(
                message_class(type_name), topic, lambda data, c=channel, t=topic: self._take(c, data, t), qos,
                raw=True))
            added.append(topic)
        return added

    def _definition(self, topic: str, type_name: str) -> str | None:
        if type_name not in self._definitions:
            try:
                self._definitions[type_name] = message_definition(type_name)
            except (OSError, ValueError) as exc:
                print(f'{self.program}: {topic}: no definition of {type_name} ({exc}); left out',
                      file=sys.stderr, flush=True)
                return None
        return self._definitions[type_name]

    def drain(self) -> int:
        """Take what waits in every subscription, without the executor; how many were taken.

        A message acknowledged to its publisher may still wait in the subscription when the stop
        comes; the executor's spin takes one ready entity per call and may run something else, so
        only taking until each subscription says it is empty proves that nothing was left."""
        before = self.count
        for subscription in self._subscriptions:
            for data in ros_adaptor.take(subscription):
                subscription.callback(data)
        return self.count - before

    def _take(self, channel: Any, data: bytes, topic: str) -> None:
        self.write(channel, data)
        self.count += 1
        if topic not in self.flowing:
            self.flowing.add(topic)
            print(f'{self.program}: {topic}: first message', flush=True)


@contextlib.contextmanager
def tap_node(name: str) -> Iterator[tuple[Any, SingleThreadedExecutor, Callable[[], bool]]]:
    """A node ``name`` in a context of its own, its executor, and whether SIGINT or SIGTERM asked
    the tool to stop (handled here, so that the sink is finished, not cut)."""
    asked = {'stop': False}

    def ask_stop(_signum: int, _frame: Any) -> None:
        asked['stop'] = True

    signal.signal(signal.SIGINT, ask_stop)
    signal.signal(signal.SIGTERM, ask_stop)
    context = Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(name, context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    try:
        yield node, executor, lambda: asked['stop']
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)


def run_tap(tap: TopicTap, executor: SingleThreadedExecutor, done: Callable[[], bool]) -> None:
    """Look at the graph every :data:`DISCOVER_S` (a line per topic added) and take messages
    until ``done()``."""
    looked = -DISCOVER_S
    while not done():
        if time.monotonic() - looked >= DISCOVER_S:
            looked = time.monotonic()
            for topic in tap.discover():
                print(f'{tap.program}: {topic}', flush=True)
        executor.spin_once(timeout_sec=0.05)
    tap.drain()                              # what had arrived when the stop came is taken too
