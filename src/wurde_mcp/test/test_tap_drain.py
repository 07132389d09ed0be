"""The recorder's tap takes, at a stop, every message that waits in its subscriptions: a message
acknowledged to its publisher but not yet taken by the executor is recorded, not lost (a CI run
once recorded 27 of 31 acknowledged messages when its drain spun the executor instead)."""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest
import rclpy
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from std_msgs.msg import String
from wurde_mcp.recording.tap import DEFAULT_EXCLUDE, TopicTap

TOPIC = '/wurde_test/drained'
COUNT = 40
DEADLINE = 30.0


@pytest.fixture
def context(ros_domain: int) -> Iterator[Context]:
    """An rclpy context of the test's own, in its domain."""
    context = Context()
    rclpy.init(context=context)
    try:
        yield context
    finally:
        rclpy.shutdown(context=context)


def test_drain_takes_every_acknowledged_message_that_no_spin_took(context: Context) -> None:
    talker = rclpy.create_node('drain_talker', context=context)
    listener = rclpy.create_node('drain_listener', context=context)
    written: list[tuple[str, bytes]] = []
    tap = TopicTap(listener, f'^{TOPIC}$', DEFAULT_EXCLUDE, lambda topic, *_: topic,
                   lambda channel, data: written.append((channel, data)), 'test')
    try:
        publisher = talker.create_publisher(String, TOPIC, QoSProfile(depth=COUNT,
                                                                      reliability=ReliabilityPolicy.RELIABLE))
        deadline = time.monotonic() + DEADLINE
        while TOPIC not in tap.channels or publisher.get_subscription_count() == 0:
            assert time.monotonic() < deadline, 'the tap did not subscribe to the topic'
            tap.discover()
            time.sleep(0.05)
        for i in range(COUNT):
            publisher.publish(String(data=f'message {i}'))
        assert publisher.wait_for_all_acked(Duration(seconds=DEADLINE)), 'not acknowledged'
        assert tap.count == 0                # nothing spun: every message still waits

        assert tap.drain() == COUNT
        assert [deserialize_message(data, String).data for _, data in written] == \
            [f'message {i}' for i in range(COUNT)]
        assert {channel for channel, _ in written} == {TOPIC} and TOPIC in tap.flowing
        assert tap.drain() == 0 and tap.count == COUNT
    finally:
        talker.destroy_node()
        listener.destroy_node()
