"""The one place that touches rclpy's internals: contexts, raw publish and take, wait sets.

WURDE's loop polls (no executor, no callbacks): a channel takes what DDS holds with
``take_message`` and publishes through the publisher's handle, and the manager waits on a wait
set of its subscriptions.  Everything that reaches below rclpy's public API is here, so that an
rclpy change is mended in one file.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Sequence
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.signals import SignalHandlerOptions


def open_node(node_name: str, ros_arguments: Sequence[str]) -> tuple[Context, Any]:
    """A fresh context (no rclpy signal handlers: the manager has its own) and a node in it."""
    context = Context()
    rclpy.init(args=['wurde', *ros_arguments], context=context,
               signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(node_name, context=context, start_parameter_services=False)
    return context, node


def publish(handle: Any, message: Any) -> None:
    """Publish ``message`` through a publisher's ``handle`` (no type check: the hot path)."""
    with handle:
        handle.publish(message)


def take(handle: Any, msg_type: type, limit: int) -> Iterator[Any]:
    """Take up to ``limit`` messages (``limit`` < 0: all) from a subscription's ``handle``."""
    with handle:
        while limit:
            limit -= 1
            result = handle.take_message(msg_type, False)
            if result is None:
                return
            yield result[0]


def take_stamped(subscription: Any) -> Iterator[tuple[Any, int]]:
    """Take everything a subscription holds, each message with the DDS source timestamp (ns,
    the writer's clock when it wrote): orders events of one writer process across topics."""
    handle = subscription.handle
    with handle:
        while True:
            result = handle.take_message(subscription.msg_type, False)
            if result is None:
                return
            yield result[0], int(result[1]['source_timestamp'])


def wait_acked(publisher: Any, timeout: float) -> bool:
    """Wait until every matched reader acknowledged what ``publisher`` sent."""
    return bool(publisher.wait_for_all_acked(Duration(seconds=max(0.0, timeout))))


class SubscriptionWaiter:
    """Waits until one of a fixed set of subscriptions has something to take."""

    def __init__(self, context: Context, subscriptions: Sequence[Any]) -> None:
        self._subscriptions = list(subscriptions)
        self._wait_set = (_rclpy.WaitSet(len(self._subscriptions), 0, 0, 0, 0, 0, context.handle)
                          if self._subscriptions else None)

    def wait(self, seconds: float) -> bool:
        """Block up to ``seconds``; return whether something arrived."""
        wait_set = self._wait_set
        if wait_set is None:
            time.sleep(max(0.0, seconds))
            return False
        wait_set.clear_entities()
        for sub in self._subscriptions:
            wait_set.add_subscription(sub.handle)
        wait_set.wait(int(max(0.0, seconds) * 1e9))
        return bool(wait_set.get_ready_entities('subscription'))

    def ready(self) -> set[int]:
        """The subscriptions (their handles' pointers) that hold something now, without waiting:
        one wait set poll is far cheaper than a ``take`` attempt on every channel."""
        if self._wait_set is None:
            return set()
        self.wait(0.0)
        return set(self._wait_set.get_ready_entities('subscription'))
