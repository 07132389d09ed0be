"""The one place that touches rclpy's internals: contexts, raw publish and take, wait sets.

WURDE's loop polls (no executor): a channel takes what DDS holds with ``take_message`` and
publishes through the publisher's handle, and the manager waits on a wait set of its
subscriptions.  What rclpy itself puts on a node — the parameter and type-description services,
the ``/clock`` subscription of ``use_sim_time`` — is served from the same loop by
:class:`NodeEntities`, as an executor would.  Everything that reaches below rclpy's public API is
here, so that an rclpy change is mended in one file.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from . import cooperative, module_context


def polled(_message: Any) -> None:
    """The callback of subscriptions that are drained by polling (never called).  Any other
    subscription on a manager's node gets its callback called from the manager's loop."""


def open_node(node_name: str, ros_arguments: Sequence[str],
              node_type: type[Node] = Node) -> tuple[Context, Node]:
    """A fresh context (no rclpy signal handlers: the manager has its own) and a node of
    ``node_type`` in it, with rclpy's parameter services (served by :class:`NodeEntities`).
    In a container (:mod:`.module_context`) the node joins the container's context instead (one
    DDS participant for all its modules), with ``ros_arguments`` as the node's own.

    :param node_name: the node's name (a legal ROS name).
    :param ros_arguments: the command line's ``--ros-args ...`` part (remappings, parameters).
    :param node_type: the rclpy node class, made as ``node_type(node_name, context=...)``.
    :returns: ``(context, node)``.
    """
    contained = module_context.current()
    if contained is not None and contained.rclpy_context is not None:
        context = contained.rclpy_context
        return context, node_type(node_name, context=context, cli_args=list(ros_arguments) or None)
    context = Context()
    rclpy.init(args=['wurde', *ros_arguments], context=context,
               signal_handler_options=SignalHandlerOptions.NO)
    return context, node_type(node_name, context=context)


class NodeEntities:
    """The node's services, and its subscriptions that have a callback (not :func:`polled`):
    what an executor would serve."""

    def __init__(self, node: Any) -> None:
        """The entities ``node`` has now; make a new one when they change.

        :param node: the manager's rclpy node.
        """
        self.services = list(node.services)
        self.subscriptions = [s for s in node.subscriptions if s.callback is not polled]
        self._serving = False

    def serve(self, ready: set[int]) -> bool:
        """Answer the requests and call the callbacks of the entities in ``ready`` (pointers
        from :meth:`SubscriptionWaiter.ready`); returns whether a service was called (it may
        have changed the node's entities: a new ``use_sim_time`` sets up ``/clock``).

        Not re-entered: a callback that steps the manager (a lifecycle transition that
        supervises while it configures) leaves further requests for after it returns, as a
        single-threaded executor would.

        :param ready: handle pointers a wait set found ready; entities not in it are skipped.
        """
        if self._serving:
            return False
        self._serving = True
        try:
            return self._serve(ready)
        finally:
            self._serving = False

    def _serve(self, ready: set[int]) -> bool:
        served = False
        for service in self.services:
            if service.handle.pointer not in ready:
                continue
            while True:
                with service.handle:
                    request, header = service.handle.service_take_request(
                        service.srv_type.Request)
                if header is None:
                    break
                service.send_response(service.callback(request, service.srv_type.Response()),
                                      header)
                served = True
        for subscription in self.subscriptions:
            if subscription.handle.pointer in ready:
                for message in take(subscription):
                    subscription.callback(message)
        return served


def publish(publisher: Any, message: Any) -> None:
    """Publish ``message`` through ``publisher``'s handle (no type check: the hot path).

    :param publisher: an rclpy publisher.
    :param message: a message of the publisher's type (a wrong type is not caught here).
    """
    handle = publisher.handle
    with handle:
        handle.publish(message)


def watched(publisher: Any) -> bool:
    """Whether any subscription is matched with ``publisher`` now.  A volatile message sent while
    none is reaches nobody, so the standard mirrors are built and sent only then (issue 39): an
    unwatched robot pays nothing for them; a reader that comes (RViz, Foxglove, ``record``) gets
    the next one once discovery has matched it.

    :param publisher: an rclpy publisher.
    """
    return publisher.get_subscription_count() > 0


def pointer(subscription: Any) -> int:
    """The identity a wait set reports ``subscription`` ready by (:meth:`SubscriptionWaiter.ready`).

    :param subscription: an rclpy subscription.
    """
    return int(subscription.handle.pointer)


def take(subscription: Any, limit: int = -1) -> Iterator[Any]:
    """Take the messages ``subscription`` holds, without an executor (the CDR bytes for a raw
    subscription).

    :param subscription: an rclpy subscription.
    :param limit: the most taken; < 0: all.
    """
    handle, msg_type, raw = subscription.handle, subscription.msg_type, bool(subscription.raw)
    with handle:
        while limit:
            limit -= 1
            result = handle.take_message(msg_type, raw)
            if result is None:
                return
            yield result[0]


def take_stamped(subscription: Any) -> Iterator[tuple[Any, int]]:
    """Take everything a subscription holds, each message with the DDS source timestamp (ns,
    the writer's clock when it wrote): orders events of one writer process across topics.

    :param subscription: an rclpy subscription.
    """
    handle = subscription.handle
    with handle:
        while True:
            result = handle.take_message(subscription.msg_type, False)
            if result is None:
                return
            yield result[0], int(result[1]['source_timestamp'])


def wait_acked(publisher: Any, timeout: float) -> bool:
    """Wait until every matched reader acknowledged what ``publisher`` sent.

    :param publisher: an rclpy publisher.
    :param timeout: the longest wait, in seconds.
    :returns: whether they did.
    """
    return bool(publisher.wait_for_all_acked(Duration(seconds=max(0.0, timeout))))


class SubscriptionWaiter:
    """Waits until one of a fixed set of subscriptions (and services) has something to take."""

    def __init__(self, context: Context, subscriptions: Sequence[Any],
                 services: Sequence[Any] = ()) -> None:
        """A wait set over these entities (none: :meth:`wait` just sleeps).

        :param context: the rclpy context the entities belong to.
        :param subscriptions: rclpy subscriptions.
        :param services: rclpy services.
        """
        self._subscriptions = list(subscriptions)
        self._services = list(services)
        self._wait_set = (_rclpy.WaitSet(len(self._subscriptions), 0, 0, 0, len(self._services),
                                         0, context.handle)
                          if self._subscriptions or self._services else None)

    def entities(self) -> tuple[list[Any], list[Any]]:
        """The subscriptions and the services waited on."""
        return self._subscriptions, self._services

    def wait(self, seconds: float) -> bool:
        """Block until something arrives or ``seconds`` pass; in a cooperative container's task,
        the other modules of its hub run meanwhile (:mod:`wurde_core.cooperative`).

        :param seconds: the longest wait.
        :returns: whether something arrived.
        """
        if seconds > 0.0:
            arrived = cooperative.wait(self, seconds)
            if arrived is not None:
                return arrived
        return self._wait(seconds)

    def _wait(self, seconds: float) -> bool:
        wait_set = self._wait_set
        if wait_set is None:
            cooperative.sleep(max(0.0, seconds))
            return False
        wait_set.clear_entities()
        for sub in self._subscriptions:
            wait_set.add_subscription(sub.handle)
        for service in self._services:
            wait_set.add_service(service.handle)
        wait_set.wait(int(max(0.0, seconds) * 1e9))
        return bool(wait_set.get_ready_entities('subscription')
                    or wait_set.get_ready_entities('service'))

    def ready(self) -> set[int]:
        """The subscriptions and services (their handles' pointers) that hold something now,
        without waiting: one wait set poll is far cheaper than a ``take`` attempt on every
        channel."""
        if self._wait_set is None:
            return set()
        self._wait(0.0)
        return (set(self._wait_set.get_ready_entities('subscription'))
                | set(self._wait_set.get_ready_entities('service')))


class WaiterGroup:
    """One wait set over the entities of several :class:`SubscriptionWaiter`s and a guard
    condition any thread may trigger: a cooperative container's hub waits on all its waiting
    modules at once (:mod:`wurde_core.cooperative`)."""

    def __init__(self, context: Context) -> None:
        """:param context: the rclpy context of every waiter's entities."""
        self.context = context
        self._guard = _rclpy.GuardCondition(context.handle)
        self._key: tuple[Any, ...] | None = None
        self._handles: list[tuple[list[Any], list[Any]]] = []
        self._pointers: list[set[int]] = []
        self._sizes = (-1, -1)
        self._wait_set: Any = None

    def trigger(self) -> None:
        """End the current or next :meth:`wait` (from any thread)."""
        self._guard.trigger_guard_condition()

    def wait(self, waiters: Sequence[SubscriptionWaiter], timeout: float) -> list[int]:
        """Wait at most ``timeout`` s (< 0: without limit) until a waiter's entities hold
        something or :meth:`trigger`; the indexes of the waiters that hold something.

        :param waiters: the waiters, the same objects from call to call while they wait (their
            handles are gathered again only when the list changes).
        :param timeout: the longest wait, s.
        """
        key = tuple(waiters)
        if key != self._key:
            self._key = key
            self._handles = [([s.handle for s in w.entities()[0]], [s.handle for s in w.entities()[1]])
                             for w in waiters]
            self._pointers = [{int(h.pointer) for h in (*subs, *servs)} for subs, servs in self._handles]
            sizes = (sum(len(h[0]) for h in self._handles), sum(len(h[1]) for h in self._handles))
            if sizes != self._sizes:
                self._wait_set = _rclpy.WaitSet(sizes[0], 1, 0, 0, sizes[1], 0, self.context.handle)
                self._sizes = sizes
        wait_set = self._wait_set
        wait_set.clear_entities()
        for subs, servs in self._handles:
            for handle in subs:
                wait_set.add_subscription(handle)
            for handle in servs:
                wait_set.add_service(handle)
        wait_set.add_guard_condition(self._guard)
        wait_set.wait(-1 if timeout < 0 else int(timeout * 1e9))
        ready = (set(wait_set.get_ready_entities('subscription'))
                 | set(wait_set.get_ready_entities('service')))
        if not ready:
            return []
        return [index for index, pointers in enumerate(self._pointers) if not pointers.isdisjoint(ready)]
