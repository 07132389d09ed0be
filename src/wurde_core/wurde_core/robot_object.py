"""RobotObject: one object per device or capability, of one interface's type (guide ch. 1, 3.2).

A program declares ``Foo("Bar")`` and registers it with its CommsManager as a supplier or a
consumer; where the stream lives and how its bytes move is the manager's business.  A supplier
sends ``data`` and ``info`` and receives ``requests``; a consumer receives ``data`` and ``info`` and
sends ``requests``.  Classes for each interface are made by :mod:`wurde_core.interfaces`.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, ClassVar

from .binding import bind
from .channel import Inbox, Outbox
from .enums import ConnectionStrategy, LockMode, RunState
from .errors import (DirectionError, InvalidTypeError, InvalidValueError, LockedError,
                     NotRegisteredError)
from .naming import relative_topic
from .qos import info_qos, stream_qos
from .ros_adaptor import polled, wait_acked
from .structs import DataStruct, InfoStruct
from .writable import DEVICE, describe_lock, lock_refusal

if TYPE_CHECKING:
    from .manager_view import ManagerView

SUPPLIER, CONSUMER = 'supplier', 'consumer'
#: Poll interval of :meth:`RobotObject.wait_for_peers`.
PEER_POLL_S = 0.01


class RobotObject:
    """Base of every interface class; use the classes in :mod:`wurde_core.interfaces`.

    ``Foo("Bar")`` names the stream directly; ``Foo(ConnectionStrategy.ASSIGNED, "EgoClient")``
    gives an alias whose stream the MCP assigns (guide 6.3).

    A class of one's own names its interface when it is defined —
    ``class ModuleLogger(RobotObject, interface='LoggerTransport')`` — and is bound to the installed
    messages when its first object is made, so defining it needs no sourced workspace.
    """

    interface_name: ClassVar[str] = ''
    description: ClassVar[dict[str, Any]] = {}
    data_type: ClassVar[type]
    info_type: ClassVar[type]
    _data_struct: ClassVar[type[DataStruct]]
    _info_struct: ClassVar[type[InfoStruct]]
    #: Objects the manager itself uses (heartbeat, MCP requests) keep flowing in Idle.
    _system: bool = False
    #: The interface this class is bound to (set by :func:`~wurde_core.binding.bind`).
    _bound_interface: ClassVar[str] = ''

    def __init_subclass__(cls, interface: str | None = None, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if interface:
            cls.interface_name = interface

    @classmethod
    def bind_interface(cls) -> None:
        """Load this class's messages and structures (once; done by the first object).

        :raises UnknownInterfaceError: when no installed package defines the interface.
        """
        if cls._bound_interface != cls.interface_name or not cls.interface_name:
            if not cls.interface_name:
                raise InvalidTypeError(f'{cls.__name__} names no interface; use a class from '
                                       'wurde_core.interfaces')
            bind(cls, cls.interface_name)

    def __init__(self, stream: str | ConnectionStrategy, name: str | None = None) -> None:
        """An unregistered object; its class is bound to its interface first.

        :param stream: the stream's name (``"Bar"``, ``"Localization/Dead-Reckoning"``), or a
            ConnectionStrategy: NORMAL (``name`` is the stream), ASSIGNED or AUTO (``name`` is
            an alias whose stream the MCP assigns, guide 6.3).
        :param name: with a strategy, the stream or alias; ignored with a stream name.
        :raises InvalidTypeError: for a strategy without a name, or neither a name nor a strategy.
        :raises UnknownInterfaceError: when no installed package defines the class's interface.
        """
        type(self).bind_interface()
        if isinstance(stream, ConnectionStrategy):
            if not name:
                raise InvalidTypeError(f'{type(self).__name__}({stream.name}, name): a name is '
                                       'needed')
            self.strategy: ConnectionStrategy | None = stream
            self.object_name = name
            self.stream: str | None = name if stream == ConnectionStrategy.NORMAL else None
        else:
            if not isinstance(stream, str) or not stream:
                raise InvalidTypeError(f'{type(self).__name__} needs a stream name or a '
                                       'ConnectionStrategy')
            self.strategy = None
            self.object_name = stream
            self.stream = stream
        self.data = self._data_struct()
        self.info = self._info_struct(owner=self, channel='info')
        self.requests = self._info_struct(owner=self, channel='requests')
        self._queue_mode = False
        self._auto_tag = True
        self._auto_timestamp = True
        self._role: str | None = None
        self._manager: ManagerView | None = None
        self._inboxes: dict[str, Inbox] = {}
        self._outboxes: dict[str, Outbox] = {}
        self._locks: dict[str, tuple[LockMode, str]] = {}
        self._arrivals = 0
        self.refused_requests = 0
        self.suppressed = 0

    # -- configuration (guide 3.2) -------------------------------------------------------------
    def set_queue_mode(self, value: bool) -> None:
        """Queue every event or keep only the newest.

        Queue mode holds for every channel the object receives (a consumer's data and info, a
        supplier's requests) and deepens the histories of what it sends, so that a burst of up
        to :data:`~wurde_core.qos.QUEUE_CAPACITY` events reaches a queue-mode peer whole.  The
        DDS history depth is fixed when a stream connects, so a change after connection
        reconnects the stream (events already taken in stay available); it always takes effect.

        :param value: True: queue mode; False: latest mode (the default).
        """
        value = bool(value)
        if value == self._queue_mode:
            return
        self._queue_mode = value
        if self.is_connected() and self.stream:
            pending = {channel: inbox for channel, inbox in self._inboxes.items()}
            self._disconnect()
            self._connect(self.stream)
            for channel, old in pending.items():
                self._inboxes[channel].adopt(old)
            if self._manager is not None:
                self._manager.entities_changed()
        for inbox in self._inboxes.values():
            inbox.set_queue_mode(self._queue_mode)

    def get_queue_mode(self) -> bool:
        """Whether the object is in queue mode."""
        return self._queue_mode

    def set_auto_tag(self, value: bool) -> None:
        """Set ``source`` of published events to the module's name (default on).

        :param value: True to tag each event sent; False leaves ``source`` as the program set it.
        """
        self._auto_tag = bool(value)

    def get_auto_tag(self) -> bool:
        """Whether published events are tagged with the module's name."""
        return self._auto_tag

    def set_auto_timestamp(self, value: bool) -> None:
        """Set ``timestamp`` of published events to the module's time (default on).

        :param value: True to stamp each event sent with ``manager.now()``; False leaves the
            timestamp as the program set it.
        """
        self._auto_timestamp = bool(value)

    def get_auto_timestamp(self) -> bool:
        """Whether published events are stamped with the module's time."""
        return self._auto_timestamp

    def set_mcp_traffic(self, value: bool) -> None:
        """Mark this object as heartbeat and MCP traffic (guide 5.2.1): it keeps flowing in every
        run state, as the manager's own heartbeat does.  For the MCP and controllers, whose job
        is to command other modules also while they themselves idle or quit.

        :param value: True for MCP traffic; False for ordinary data (the default).
        """
        self._system = bool(value)

    # -- state ---------------------------------------------------------------------------------
    @property
    def role(self) -> str | None:
        """``'supplier'``, ``'consumer'`` or ``None`` before registration."""
        return self._role

    def is_connected(self) -> bool:
        """Whether the object has its stream (an ASSIGNED or AUTO one waits for the MCP)."""
        return bool(self._inboxes or self._outboxes)

    @property
    def data_drops(self) -> int:
        """Data events lost (queue overflow past the cap, or dropped on the way)."""
        return self._drops('data')

    @property
    def info_drops(self) -> int:
        """Info events lost."""
        return self._drops('info')

    @property
    def request_drops(self) -> int:
        """Request events lost."""
        return self._drops('request')

    def _drops(self, channel: str) -> int:
        inbox = self._inboxes.get(channel)
        return inbox.drops if inbox else 0

    # -- peers -----------------------------------------------------------------------------------
    def _outgoing(self) -> Outbox | None:
        """The channel this object sends on most: a supplier's data, a consumer's requests."""
        return self._outboxes.get('data' if self._role == SUPPLIER else 'request')

    def peers(self, channel: str | None = None) -> int:
        """Matched peers right now: the readers of a channel this object sends, the writers of
        one it receives.  0 before the stream is connected.

        :param channel: ``data``, ``info`` or ``request``; None: the one this object sends on
            most, a supplier's data or a consumer's requests.
        """
        if channel is None:
            outbox = self._outgoing()
            return outbox.subscribers() if outbox is not None else 0
        outbox = self._outboxes.get(channel)
        if outbox is not None:
            return outbox.subscribers()
        inbox = self._inboxes.get(channel)
        return inbox.subscription.get_publisher_count() if inbox is not None else 0

    def wait_for_peers(self, timeout: float, count: int = 1, channel: str | None = None) -> bool:
        """Wait until enough peers are matched (see :meth:`peers`).  Discovery runs in DDS's own
        threads, so this needs no ``run_update``.

        :param timeout: the longest wait, in seconds.
        :param count: how many peers are enough.
        :param channel: as for :meth:`peers`; None: the outgoing channel.
        :returns: whether at least ``count`` peers are matched.
        """
        deadline = time.monotonic() + timeout
        while self.peers(channel) < count:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return False
            time.sleep(min(PEER_POLL_S, remaining))
        return True

    def received(self, channel: str = 'data') -> int:
        """Events taken in since connection (and kept across a queue-mode reconnection).

        :param channel: ``data``, ``info`` or ``request``; 0 for one the object does not receive.
        """
        inbox = self._inboxes.get(channel)
        return inbox.received if inbox is not None else 0

    def wait_delivered(self, timeout: float, channel: str | None = None) -> bool:
        """Wait until every matched reader acknowledged what this object sent.

        :param timeout: the longest wait, in seconds.
        :param channel: ``data``, ``info`` or ``request``, one the object sends; None: its
            outgoing channel (see :meth:`peers`).
        :returns: whether they did (False for a channel the object does not send).
        """
        outbox = self._outboxes.get(channel) if channel else self._outgoing()
        if outbox is None:
            return False
        return wait_acked(outbox.publisher, timeout)

    # -- receiving -----------------------------------------------------------------------------
    def new_data(self) -> bool:
        """Whether a data event waits for :meth:`get_next_data`."""
        inbox = self._inboxes.get('data')
        return inbox.pending() if inbox else False

    def new_info(self) -> bool:
        """Whether an info event waits for :meth:`get_next_info`."""
        inbox = self._inboxes.get('info')
        return inbox.pending() if inbox else False

    def new_request(self) -> bool:
        """Whether a request waits for :meth:`get_next_request` (suppliers)."""
        inbox = self._inboxes.get('request')
        return inbox.pending() if inbox else False

    def get_next_data(self) -> bool:
        """Load the next data event into ``data``; False when there was none."""
        return self._load('data', self.data)

    def get_next_info(self) -> bool:
        """Load the next info event into ``info``; False when there was none."""
        loaded = self._load('info', self.info)
        if loaded:
            self._locks = {lock.field: (LockMode(lock.mode), lock.owner)
                           for lock in self.info.ros_message().locks}
        return loaded

    def get_next_request(self) -> bool:
        """Load the next request into ``requests``; False when there was none."""
        return self._load('request', self.requests)

    def _load(self, channel: str, struct: Any) -> bool:
        inbox = self._inboxes.get(channel)
        message = inbox.pop() if inbox else None
        if message is None:
            return False
        struct._adopt(message)
        return True

    # -- sending -------------------------------------------------------------------------------
    def publish_data(self) -> bool:
        """Send ``data`` (suppliers).  False when the run state lets no data flow.

        :raises DirectionError: on a consumer.  :raises NotRegisteredError: before registration.
        """
        self._need(SUPPLIER, 'publish data')
        return self._send('data', self.data.ros_message())

    def publish_info(self) -> bool:
        """Send ``info`` with the supplier's locks (suppliers); late consumers get it too."""
        self._need(SUPPLIER, 'publish info')
        message = self.info.ros_message()
        message.set_fields = []
        message.locks = [self._lock_msg(field, mode, owner)
                         for field, (mode, owner) in sorted(self._locks.items())]
        sent = self._send('info', message)
        self.info._written().clear()
        return sent

    def publish_request(self) -> bool:
        """Send the members of ``requests`` set since the last request (consumers)."""
        self._need(CONSUMER, 'publish requests')
        message = self.requests.ros_message()
        message.set_fields = sorted(self.requests._written())
        sent = self._send('request', message)
        if sent:
            self.requests._written().clear()
        return sent

    def _need(self, role: str, what: str) -> None:
        if self._role is None:
            raise NotRegisteredError(f'{self._label()}: register it with a CommsManager before '
                                     f'you {what}')
        if self._role != role:
            raise DirectionError(f'{self._label()} is a {self._role}; only a {role} may {what}')

    def _send(self, channel: str, message: Any) -> bool:
        outbox = self._outboxes.get(channel)
        manager = self._manager
        if outbox is None or manager is None:
            self.suppressed += 1
            return False
        if not self._system and manager.state != RunState.RUN:
            self.suppressed += 1
            return False
        if self._auto_tag:
            message.header.source = manager.name
        if self._auto_timestamp:
            manager.now().to_msg(message.header.stamp)
        outbox.send(message)
        return True

    # -- locks (suppliers hold them, guide 3.2.4) ----------------------------------------------
    def lock(self, mode: LockMode, owner: str = '') -> None:
        """Lock the whole device: who may change any info member (suppliers only).

        :param mode: who may: SUPPLIERS, CONSUMERS, or PROCESS (the process ``owner`` only);
            NONE removes the lock.
        :param owner: the module name of the one process a PROCESS lock allows.
        :raises DirectionError: on a consumer.
        :raises InvalidValueError: for a PROCESS lock without ``owner``.
        """
        self.set_lock(DEVICE, mode, owner)

    def unlock(self) -> None:
        """Remove the device-wide lock."""
        self.set_lock(DEVICE, LockMode.NONE, '')

    def set_lock(self, field: str, mode: LockMode, owner: str = '') -> None:
        """Set a member's lock and tell the consumers (the info is published again when the
        object is a connected supplier).

        :param field: the info member's name; empty: the whole device.
        :param mode: as for :meth:`lock`; NONE removes the member's lock.
        :param owner: the module name of the one process a PROCESS lock allows.
        :raises DirectionError: on a consumer.
        :raises InvalidValueError: for a PROCESS lock without ``owner``.
        """
        if self._role == CONSUMER:
            raise DirectionError(f'{self._label()}: only the supplier holds locks')
        mode = LockMode(mode)
        if mode == LockMode.PROCESS and not owner:
            raise InvalidValueError('a PROCESS lock needs the owning process name')
        if mode == LockMode.NONE:
            self._locks.pop(field, None)
        else:
            self._locks[field] = (mode, owner)
        if self._role == SUPPLIER and self.is_connected():
            self.publish_info()

    def locks(self) -> dict[str, tuple[LockMode, str]]:
        """Locks in force: held (supplier) or last announced by the supplier (consumer)."""
        return dict(self._locks)

    @staticmethod
    def _lock_msg(field: str, mode: LockMode, owner: str) -> Any:
        from wurde_interfaces.msg import Lock
        return Lock(field=field, mode=int(mode), owner=owner)

    def _process_name(self) -> str:
        return self._manager.name if self._manager is not None else ''

    def _check_write(self, channel: str, field: str) -> None:
        """Called by Writable.set_value: enforce direction and locks for this process."""
        if self._role is None:
            return
        if channel == 'info' and self._role == CONSUMER:
            raise DirectionError(f'{self._label()}: a consumer\'s info is read-only; set '
                                 f'requests.{field} and publish_request() instead')
        if channel == 'requests' and self._role == SUPPLIER:
            raise DirectionError(f'{self._label()}: a supplier\'s requests are what consumers '
                                 f'sent; change info.{field} instead')
        refusal = lock_refusal(self._locks, field, self._role, self._process_name())
        if refusal is not None:
            raise LockedError(f'{self._label()}: {field} is {describe_lock(*refusal)}; '
                              f'{self._process_name() or "this process"} ({self._role}) may not '
                              'change it')

    def _accept_request(self, message: Any) -> bool:
        """Supplier side: drop a request that writes a locked member (counted and logged)."""
        if not self._locks:
            return True
        fields = list(message.set_fields) or list(self.requests.field_names())
        for field in fields:
            refusal = lock_refusal(self._locks, field, CONSUMER, message.header.source)
            if refusal is not None:
                self.refused_requests += 1
                if self._manager is not None:
                    self._manager.log_warning(
                        f'{self._label()}: refused request from "{message.header.source}": '
                        f'{field} is {describe_lock(*refusal)}')
                return False
        return True

    # -- connection (called by the CommsManager) -----------------------------------------------
    def _register(self, manager: 'ManagerView', role: str) -> None:
        self._manager = manager
        self._role = role

    def _unregister(self) -> None:
        self._manager = None
        self._role = None

    def _connect(self, stream: str) -> None:
        """Create this object's publishers and subscriptions on ``stream``."""
        manager = self._manager
        assert manager is not None and self._role is not None
        node = manager.node
        self.stream = stream
        queue_qos = stream_qos(self._queue_mode)
        if self._role == SUPPLIER:
            self._outboxes['data'] = Outbox(node.create_publisher(
                self.data_type, relative_topic(stream, 'data'), queue_qos))
            self._outboxes['info'] = Outbox(node.create_publisher(
                self.info_type, relative_topic(stream, 'info'), info_qos(self._queue_mode)))
            self._inboxes['request'] = Inbox(node.create_subscription(
                self.info_type, relative_topic(stream, 'request'), polled, queue_qos),
                self._queue_mode, accept=self._accept_request)
        else:
            self._inboxes['data'] = Inbox(node.create_subscription(
                self.data_type, relative_topic(stream, 'data'), polled, queue_qos), self._queue_mode)
            self._inboxes['info'] = Inbox(node.create_subscription(
                self.info_type, relative_topic(stream, 'info'), polled, info_qos(self._queue_mode)),
                self._queue_mode)
            self._outboxes['request'] = Outbox(node.create_publisher(
                self.info_type, relative_topic(stream, 'request'), queue_qos))

    def _disconnect(self) -> None:
        manager = self._manager
        if manager is not None and manager.node is not None:
            for inbox in self._inboxes.values():
                manager.node.destroy_subscription(inbox.subscription)
            for outbox in self._outboxes.values():
                manager.node.destroy_publisher(outbox.publisher)
        self._inboxes.clear()
        self._outboxes.clear()

    def _drain(self, ready: set[int] | None = None) -> int:
        """Take in everything that arrived (only from the subscriptions in ``ready``, pointers of
        those a wait set found holding something, when given); return how many events."""
        taken = 0
        for inbox in self._inboxes.values():
            if ready is None or inbox.pointer in ready:
                taken += inbox.drain()
        if taken:
            self._arrivals += taken
        return taken

    def _discard_pending(self) -> int:
        """Forget events taken in and not yet read (a Reset); return how many."""
        return sum(inbox.discard() for inbox in self._inboxes.values())

    def _subscriptions(self) -> list[Any]:
        return [inbox.subscription for inbox in self._inboxes.values()]

    def _label(self) -> str:
        return f'{self.interface_name}("{self.object_name}")'

    def __repr__(self) -> str:
        return (f'<{self._label()} {self._role or "unregistered"}'
                f'{" on " + self.stream if self.stream else ""}>')
