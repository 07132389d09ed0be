"""The two ends of a channel: :class:`Outbox` publishes, :class:`Inbox` takes in.

An inbox drains its subscription with ``take_message`` (no executor, no callbacks: WURDE's polling
loop takes what arrived).  In latest mode it keeps the newest event (older ones are meant to be
overwritten, so nothing is counted).  In queue mode it keeps up to
:data:`~wurde_core.qos.QUEUE_CAPACITY` events, drops the oldest beyond that and counts every loss,
including events DDS itself dropped because the consumer fell more than the history depth behind:
those show as gaps in a sender's ``header.sequence``.  A sender is a source's process (its
``header.session``: a restarted supplier counts from 1 again).  At first contact with one, a gap counts
only if that drain found the history full (it overflowed); otherwise the consumer simply joined a
running stream late and what was sent before it existed is not a loss.
"""

from __future__ import annotations

import collections
import secrets
from collections.abc import Callable
from typing import Any

from .qos import QUEUE_CAPACITY
from .ros_adaptor import pointer, publish, take


#: This process's ``header.session`` (:mod:`wurde_core.sender_watch`): drawn once, never 0.
SESSION = secrets.randbits(63) | 1


class Outbox:
    """A publisher that numbers what it sends (``header.sequence``) and says which process sent
    it (``header.session``)."""

    __slots__ = ('publisher', 'sequence')

    def __init__(self, publisher: Any) -> None:
        """An outbox counting from 1.

        :param publisher: the channel's rclpy publisher.
        """
        self.publisher = publisher
        self.sequence = 0

    def send(self, message: Any) -> None:
        """Publish ``message`` with the next sequence number and this process's session.

        :param message: a Data or Info message of the channel's type; its header is written.
        """
        self.sequence += 1
        message.header.sequence = self.sequence
        message.header.session = SESSION
        publish(self.publisher, message)

    def subscribers(self) -> int:
        """Matched subscriptions right now."""
        return self.publisher.get_subscription_count()


class Inbox:
    """A subscription drained by polling, in latest or queue mode."""

    __slots__ = ('subscription', 'pointer', 'queue', 'latest', 'fresh', 'drops',
                 'received', '_last_seq', 'accept')

    def __init__(self, subscription: Any, queue_mode: bool,
                 accept: Callable[[Any], bool] | None = None) -> None:
        """An empty inbox.

        :param subscription: the channel's rclpy subscription (its callback is never called).
        :param queue_mode: keep every event (up to the cap) rather than the newest only.
        :param accept: a filter of each message taken (a supplier's lock check of requests): a
            message it refuses is dropped and not counted as received; None: every message.
        """
        self.subscription = subscription
        self.pointer = pointer(subscription)
        self.queue: collections.deque[Any] | None = collections.deque() if queue_mode else None
        self.latest: Any = None
        self.fresh = False
        self.drops = 0
        self.received = 0
        self._last_seq: dict[tuple[str, int], int] = {}
        self.accept = accept

    def set_queue_mode(self, queue_mode: bool) -> None:
        """Switch modes; what was taken in and not read stays available (in latest mode only
        the newest of it).

        :param queue_mode: True: queue mode; False: latest mode.
        """
        if queue_mode and self.queue is None:
            self.queue = collections.deque()
            if self.fresh and self.latest is not None:
                self.queue.append(self.latest)
        elif not queue_mode and self.queue is not None:
            if self.queue:
                self.latest, self.fresh = self.queue[-1], True
            self.queue = None

    def adopt(self, old: 'Inbox') -> None:
        """Take over what ``old`` held and counted.

        :param old: the same channel's inbox before a reconnection.
        """
        if old.queue is not None:
            self.queue = collections.deque(old.queue) if self.queue is not None else None
            if self.queue is None and old.queue:
                self.latest, self.fresh = old.queue[-1], True
        if old.fresh and old.latest is not None:
            if self.queue is not None:
                self.queue.append(old.latest)
            else:
                self.latest, self.fresh = old.latest, True
        self.drops += old.drops
        self.received += old.received
        self._last_seq.update(old._last_seq)

    def discard(self) -> int:
        """Forget what was taken in and not yet read (a Reset); return how many events."""
        count = len(self.queue) if self.queue is not None else int(self.fresh)
        if self.queue is not None:
            self.queue.clear()
        self.fresh = False
        return count

    def drain(self) -> int:
        """Take in what DDS holds for this subscription; return how many events.

        Latest mode takes everything and keeps the newest.  Queue mode takes only as many as the
        queue has room for: the rest waits in the DDS history (as deep again), so a consumer that
        reads slower than its supplier writes loses events only when both are full, and those
        losses show up as sequence gaps.
        """
        taken = 0
        queue = self.queue
        room = QUEUE_CAPACITY - len(queue) if queue is not None else -1
        first_gaps = 0
        last_seq = self._last_seq
        accept = self.accept
        for message in take(self.subscription, room):
            if queue is not None:
                # Sequence gaps (inlined: this is the hot path of every queue-mode stream).
                header = message.header
                sequence = header.sequence
                if sequence:
                    sender = (header.source, header.session)
                    last = last_seq.get(sender)
                    last_seq[sender] = sequence
                    if last is None:
                        first_gaps += sequence - 1
                    elif sequence > last + 1:
                        self.drops += sequence - last - 1
            if accept is not None and not accept(message):
                continue
            taken += 1
            if queue is not None:
                queue.append(message)
            else:
                self.latest = message
                self.fresh = True
        if first_gaps and taken >= QUEUE_CAPACITY:
            self.drops += first_gaps
        self.received += taken
        return taken

    def pending(self) -> bool:
        """Whether an event is waiting for ``get_next_*``."""
        return bool(self.queue) if self.queue is not None else self.fresh

    def pop(self) -> Any:
        """The next event (queue mode: the oldest; latest mode: the newest), or ``None``."""
        if self.queue is not None:
            return self.queue.popleft() if self.queue else None
        if not self.fresh:
            return None
        self.fresh = False
        return self.latest
