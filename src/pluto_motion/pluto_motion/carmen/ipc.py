"""The IPC side of CARMEN on a CommsManager: subscriptions, their handlers, timers, dispatch.

Programming with CARMEN 3.0.1: a subscription names the message memory (``msg``; ``None``: a
static message the library allocates, one per message name) and a handler (``None``: the memory is
only updated); the same memory is re-used for every message of that name and passed to the
handler.  CARMEN_SUBSCRIBE_LATEST hands over only the newest message of each dispatch turn,
CARMEN_SUBSCRIBE_ALL every one (up to :data:`~wurde_core.qos.QUEUE_CAPACITY` behind, CARMEN's
1000), CARMEN_UNSUBSCRIBE ends the subscription.

Underneath, each stream read is one WURDE consumer (a :class:`Feed`) of the program's
CommsManager, in queue mode while any subscription on it wants every message.  Messages are taken
in by every turn of the loop (also while a query waits) and handed to handlers only by
:meth:`CarmenIpc.sleep` / :meth:`CarmenIpc.dispatch`, in the program's own thread.
"""

from __future__ import annotations

import collections
import dataclasses
import math
import sys
import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, RunState
from wurde_core.errors import InvalidTypeError, InvalidValueError
from wurde_core.interfaces import Egomotion
from wurde_core.qos import QUEUE_CAPACITY
from wurde_core.robot_object import RobotObject

from pluto_nav.pose_history import PoseHistory

from .messages import CARMEN_SUBSCRIBE_ALL, CARMEN_UNSUBSCRIBE, carmen_subscribe_t

Handler = Callable[[Any], None]
#: Fills a message from one event; False when the event gives no message (yet).
Fill = Callable[[Any, Any], 'bool | None']
TimerHandler = Callable[[Any, int, int], None]

#: Seconds of odometry kept for placing scans and poses (CARMEN's robot interpolates it).
HISTORY_S = 5.0


class Feed:
    """One stream this program reads: a consumer, the events taken in and not yet handed out."""

    def __init__(self, manager: CommsManager, obj: RobotObject, every: bool) -> None:
        """Register ``obj`` as a consumer of ``manager``.

        :param manager: the program's manager.
        :param obj: the consumer of the stream, not registered yet.
        :param every: whether its first reader wants every message (queue mode) or the newest.
        """
        self.manager, self.obj = manager, obj
        obj.set_queue_mode(every)           # before connecting: a switch later reconnects
        manager.register_consumer(obj)
        self.users: dict[str, bool] = {}
        self.pending: collections.deque[Any] = collections.deque(maxlen=QUEUE_CAPACITY)
        self.latest: Any = None
        self.dropped = 0
        #: Called with each batch taken in (oldest first), before any handler sees it.
        self.watchers: list[Callable[[list[Any]], None]] = []

    def want(self, user: str, every: bool) -> None:
        """``user`` reads this stream (``every``: each message, queue mode).

        :param user: the reader: a CARMEN message name, or an internal name starting with ``_``.
        :param every: whether it wants every message; the stream is in queue mode while any
            reader does.
        """
        self.users[user] = every
        self.obj.set_queue_mode(any(self.users.values()))

    def release(self, user: str) -> bool:
        """``user`` no longer reads; whether nobody does.

        :param user: the reader named to :meth:`want`.
        """
        self.users.pop(user, None)
        self.obj.set_queue_mode(any(self.users.values()))
        return not self.users

    def collect(self) -> list[Any]:
        """Take in what arrived (data views, oldest first), keep it for the next hand-out."""
        taken = []
        view = type(self.obj.data)
        while self.obj.get_next_data():
            taken.append(view(self.obj.data.ros_message()))
        while self.obj.get_next_info():
            pass                                    # obj.info: the newest settings
        if taken:
            overflow = len(self.pending) + len(taken) - QUEUE_CAPACITY
            self.dropped += max(overflow, 0)
            self.pending.extend(taken)
            self.latest = taken[-1]
            for watcher in self.watchers:
                watcher(taken)
        return taken


@dataclasses.dataclass
class Subscription:
    """One message name's memory, handler and mode, and the source of its events."""

    source: str
    fill: Fill
    msg: Any
    handler: Handler | None
    how: carmen_subscribe_t

    def deliver(self, events: list[Any]) -> int:
        """Fill the memory from ``events`` (only the newest, or each) and call the handler.

        :param events: the events taken in since the last hand-out, oldest first.
        :returns: how many messages were filled (an event that gives no message is skipped).
        """
        handled = 0
        for event in (events if self.how == CARMEN_SUBSCRIBE_ALL else events[-1:]):
            if self.fill(self.msg, event) is False:
                continue
            handled += 1
            if self.handler is not None:
                self.handler(self.msg)
        return handled


@dataclasses.dataclass
class Timer:
    """carmen_ipc_addPeriodicTimer's handler, called ``handler(client_data, now_ms, due_ms)``."""

    interval: float
    handler: TimerHandler
    client_data: Any
    due: float


class CarmenIpc:
    """CARMEN's IPC connection of one program, on ``manager``; ``streams`` names the streams of
    the robot (keys ``base``, ``frontlaser``, ``rearlaser``, ``navigator``, ``map_server``)."""

    def __init__(self, manager: CommsManager, streams: dict[str, str]) -> None:
        """Connect nothing yet: feeds are made by the first subscription that reads them.

        :param manager: the program's manager (its loop is run by :meth:`sleep` and
            :meth:`dispatch`).
        :param streams: the robot's stream names by key (``base``, ``frontlaser``, ``rearlaser``,
            ``navigator``, ``map_server``).
        """
        self.manager = manager
        self.streams = dict(streams)
        self.feeds: dict[str, Feed] = {}
        self.subscriptions: dict[str, Subscription] = {}
        self.static: dict[str, Any] = {}
        self.timers: list[Timer] = []
        self.odometry = PoseHistory(keep_s=HISTORY_S)
        self.velocity = (0.0, 0.0)
        #: Events made from other events (the navigator's stops), by source name.
        self.derived: dict[str, collections.deque[Any]] = {}
        #: Called every turn after the feeds (proxies that resend held requests).
        self.collectors: list[Callable[[], object]] = []
        #: Helpers made on first use (the drive's proxy, the navigator's link), by name.
        self.links: dict[str, Any] = {}
        self.closed = False
        self._delivering = False

    # -- feeds and subscriptions ------------------------------------------------------------------
    def feed(self, key: str, make: Callable[[], RobotObject], user: str, every: bool) -> Feed:
        """The feed ``key`` (made by ``make`` on first use), read by ``user``.

        :param key: the feed's name (its stream's, as a rule).
        :param make: makes the consumer, called only when the feed is new.
        :param user: the reader (:meth:`Feed.want`).
        :param every: whether ``user`` wants every message.
        """
        feed = self.feeds.get(key)
        if feed is None:
            feed = self.feeds[key] = Feed(self.manager, make(), every)
        feed.want(user, every)
        return feed

    def odometry_feed(self) -> Feed:
        """The base's odometry, every sample kept in :attr:`odometry` for placing scans."""
        stream = f'{self.streams["base"]}Motion'
        feed = self.feed(stream, lambda: Egomotion(stream), '_history', True)
        if self._remember not in feed.watchers:
            feed.watchers.append(self._remember)
        return feed

    def _remember(self, samples: list[Any]) -> None:
        for d in samples:
            loc = d.location
            self.odometry.add(d.timestamp.get_seconds(), (loc.x(), loc.y(), loc.theta()))
            self.velocity = (float(d.tv), float(d.rv))

    def subscribe(self, name: str, message_type: type, source: str, fill: Fill, msg: Any,
                  handler: Handler | None, how: int) -> Any:
        """CARMEN's subscribe (3.0.1) for message ``name``; returns the memory used (None when
        unsubscribing).

        :param name: the CARMEN message name; one subscription per name, a new one replaces it.
        :param message_type: the message class, for the library's static memory.
        :param source: a feed key or a derived source (:attr:`derived`).
        :param fill: fills the memory from one event; False when the event gives no message.
        :param msg: the memory to fill, a ``message_type``; None: the static one of ``name``.
        :param handler: called with the memory after each fill (None: the memory is only
            updated).
        :param how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
        :raises InvalidTypeError: a handler that is not callable, or a memory of another type.
        :raises InvalidValueError: another ``how``.
        """
        how = mode(how)
        if handler is not None and not callable(handler):
            raise InvalidTypeError(f'{name}: the handler must be callable or None, not {handler!r}')
        if how == CARMEN_UNSUBSCRIBE:
            old = self.subscriptions.pop(name, None)
            if old is not None and old.source in self.feeds:
                self._release(old.source, name)
            return None
        if msg is None:
            msg = self.static.setdefault(name, message_type())
        elif not isinstance(msg, message_type):
            raise InvalidTypeError(f'{name}: msg must be a {message_type.__name__} or None, not '
                                   f'{type(msg).__name__}')
        if source in self.feeds:
            self.feeds[source].want(name, how == CARMEN_SUBSCRIBE_ALL)
        self.subscriptions[name] = Subscription(source, fill, msg, handler, how)
        return msg

    def _release(self, key: str, user: str) -> None:
        feed = self.feeds[key]
        if feed.release(user):
            self.manager.unregister(feed.obj)
            del self.feeds[key]

    # -- the loop ----------------------------------------------------------------------------------
    def collect(self) -> None:
        """Take in what arrived on every feed (no handler runs)."""
        for feed in list(self.feeds.values()):
            feed.collect()
        for collector in self.collectors:
            collector()

    def deliver(self) -> int:
        """Hand what was taken in to the subscriptions (3.0.1), then forget it."""
        handled = 0
        self._delivering = True
        try:
            for sub in list(self.subscriptions.values()):
                feed = self.feeds.get(sub.source)
                events = list(feed.pending) if feed is not None else list(self.derived.get(sub.source, ()))
                handled += sub.deliver(events)
        finally:
            self._delivering = False
            for feed in self.feeds.values():
                feed.pending.clear()
            for queue in self.derived.values():
                queue.clear()
        return handled

    def turn(self) -> bool:
        """One turn: the manager's update, take in, hand out (not from inside a handler), timers.
        False when the program is to quit; a registration run (``-r``) ends here, once the
        manager has reported the streams subscribed so far to the MCP."""
        if self.closed:
            return False
        if self.manager.run_update() != RunState.RUN:
            if self.manager.options.registration:
                self.close()                # the MCP's registration pass (-r): reported, so end
                sys.exit(0)
            return False
        self.collect()
        if not self._delivering:
            self.deliver()
            self._fire_timers()
        return True

    def sleep(self, seconds: float) -> bool:
        """carmen_ipc_sleep: handle messages and timers for ``seconds``; False on Quit.

        :param seconds: how long (s), at least 0.
        :raises InvalidValueError: a negative or non-finite time.
        """
        if not math.isfinite(seconds) or seconds < 0:
            raise InvalidValueError(f'carmen_ipc_sleep({seconds}): a time >= 0 in seconds')
        deadline = time.monotonic() + seconds
        while self.turn() and not self.closed:
            left = deadline - time.monotonic()
            if left <= 0:
                return True
            self.manager.wait(min(left, self._next_timer()))
        return False

    def dispatch(self) -> None:
        """carmen_ipc_dispatch: handle messages and timers until the program is to quit (or a
        handler disconnects)."""
        while self.turn() and not self.closed:
            self.manager.wait(self._next_timer())

    def wait_for(self, ready: Callable[[], bool], timeout: float) -> bool:
        """Run the loop (taking in, not handing out) until ``ready()``; False after ``timeout``.

        :param ready: asked after each turn.
        :param timeout: the longest wait (s); also False at once when the program is to quit.
        """
        deadline = time.monotonic() + timeout
        while not ready():
            left = deadline - time.monotonic()
            if left <= 0 or self.closed or self.manager.run_update() != RunState.RUN:
                return False
            self.collect()
            if not ready():
                self.manager.wait(min(left, 0.05))
        return True

    # -- timers ------------------------------------------------------------------------------------
    def add_timer(self, interval: float, handler: TimerHandler, client_data: Any) -> Timer:
        """carmen_ipc_addPeriodicTimer: call ``handler`` every ``interval`` s from the loop.

        :param interval: the period (s), above 0; a timer that falls a period behind skips ahead.
        :param handler: called ``handler(client_data, now_ms, due_ms)`` (monotonic ms).
        :param client_data: passed to the handler as it is.
        :raises InvalidValueError: an interval that is not above 0.
        :raises InvalidTypeError: a handler that is not callable.
        """
        if not (math.isfinite(interval) and interval > 0):
            raise InvalidValueError(f'carmen_ipc_addPeriodicTimer: interval {interval}: seconds > 0')
        if not callable(handler):
            raise InvalidTypeError(f'carmen_ipc_addPeriodicTimer: handler {handler!r} is not callable')
        timer = Timer(float(interval), handler, client_data, time.monotonic() + interval)
        self.timers.append(timer)
        return timer

    def _next_timer(self) -> float:
        """Seconds to the next timer (a slice when there is none, to see a Quit promptly)."""
        now = time.monotonic()
        return max(min((t.due - now for t in self.timers), default=0.1), 0.0)

    def _fire_timers(self) -> None:
        now = time.monotonic()
        for timer in list(self.timers):
            if timer.due <= now:
                due = timer.due
                timer.due = due + timer.interval if now - due < timer.interval else now + timer.interval
                timer.handler(timer.client_data, int(now * 1000), int(due * 1000))

    def close(self) -> None:
        """carmen_ipc_disconnect: release the streams and the manager (idempotent)."""
        if not self.closed:
            self.closed = True
            self.manager.clean_up()


def mode(how: int) -> carmen_subscribe_t:
    """``subscribe_how`` as CARMEN's enum.

    :param how: CARMEN_UNSUBSCRIBE, CARMEN_SUBSCRIBE_LATEST or CARMEN_SUBSCRIBE_ALL (or its value).
    :raises InvalidValueError: for any other value.
    """
    try:
        return carmen_subscribe_t(how)
    except ValueError:
        raise InvalidValueError(f'subscribe_how {how!r}: one of CARMEN_UNSUBSCRIBE, CARMEN_SUBSCRIBE_LATEST, '
                                'CARMEN_SUBSCRIBE_ALL') from None


def warn(text: str) -> None:
    """A CARMEN-style warning on stderr (CARMEN's interface libraries print theirs there).

    :param text: the warning, printed after ``carmen:``.
    """
    print(f'carmen: {text}', file=sys.stderr, flush=True)
