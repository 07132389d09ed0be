"""The module's heartbeat: keep-alive to the MCP and the channel it commands states through.

Seed: WURDE Programming Guide 3.4.7 and 5.2.1.  Each module supplies a ``Heartbeat`` object on
stream ``heartbeat/<module name>``: data carries the TTL (how long to wait for the next beat),
info describes the process (run state, pid, host, managed state, locale, the MCP it belongs to,
what it supplies and consumes), and requests that set ``state`` change the module's run state — from the MCP or any
controller (``Heartbeat("heartbeat/FooServer")`` as a consumer, ``requests.state.set_value``).

The heartbeat knows nothing of the manager: the manager tells it what to describe and when to
beat, and applies the state commands it returns.
"""

from __future__ import annotations

import socket
import time
from collections.abc import Sequence

from . import module_context
from .enums import ProcessLocale, ProcessType, RunState
from .interfaces import robot_object_class
from .robot_object import SUPPLIER, RobotObject

STREAM_PREFIX = 'heartbeat/'
#: Environment variable the MCP sets for the modules it starts: their managed state from the
#: configuration (guide 6.1), by name.  A module started by hand has none and reports itself
#: unmanaged, which is what it is: no MCP restarts it.
MANAGED_ENV = 'WURDE_MCP_MANAGED'
#: Environment variable the MCP sets for the modules it starts: how many times it has started
#: this module before in its run (0 the first time).  A module whose state outlives its process
#: (the localModule's pose) picks it up again when this is not 0.
RESTART_ENV = 'WURDE_MCP_RESTART'
#: Environment variable naming the MCP a module belongs to: the MCP sets it (its own CommsManager
#: name) for the modules it starts, and a module started by hand on a host whose MCP is not named
#: ``MCP`` is given it in its shell.  Several MCPs can then share a domain, one per host: each
#: module talks to its own MCP's streams only (:func:`wurde_core.mcp_client.mcp_stream`), and
#: its heartbeat says which MCP it belongs to, so that no other MCP commands it.
MCP_ENV = 'WURDE_MCP_NAME'
#: The seed's MCP: the name a module assumes when :data:`MCP_ENV` is not set.
DEFAULT_MCP = 'MCP'
#: Longest gap between beats whatever the TTL, so that a beat lost before the MCP had discovered
#: this module is soon followed by another.
MAX_BEAT_INTERVAL_S = 1.0


def managed_state() -> ProcessType:
    """This process's managed state, as the MCP that started it told it (:data:`MANAGED_ENV`)."""
    try:
        return ProcessType[module_context.getenv(MANAGED_ENV, 'UNMANAGED')]
    except KeyError:
        return ProcessType.UNMANAGED


def mcp_owner() -> str:
    """The MCP this process belongs to (:data:`MCP_ENV`); empty when none is named (started by
    hand under the seed's single MCP, which may then command it)."""
    return module_context.getenv(MCP_ENV).strip()


def mcp_name() -> str:
    """The name of the MCP this process talks to: :func:`mcp_owner`, else :data:`DEFAULT_MCP`."""
    return mcp_owner() or DEFAULT_MCP


def restart_count() -> int:
    """How many times the MCP that started this process had started its module before
    (:data:`RESTART_ENV`); 0 for a first start or a module started by hand."""
    try:
        return max(0, int(module_context.getenv(RESTART_ENV, '0')))
    except ValueError:
        return 0


def heartbeat_stream(module: str) -> str:
    """The stream a module's heartbeat lives on (``heartbeat/<module>``).

    :param module: the module's (CommsManager's) name.
    """
    return STREAM_PREFIX + module


class ModuleHeartbeat:
    """Sends the beats and the process description, takes in state commands."""

    def __init__(self, module: str) -> None:
        """A Heartbeat object on the module's stream, in queue mode; the manager registers it.

        :param module: the module's name.
        """
        self.obj: RobotObject = robot_object_class('Heartbeat')(heartbeat_stream(module))
        self.obj._system = True
        self.obj.set_queue_mode(True)  # never lose a state command
        self._last_beat: float | None = None
        self.beats = 0

    def describe(self, state: RunState, objects: Sequence[RobotObject], *,
                 trust_ttl: bool = False, quit_time: float = 0.0) -> None:
        """Publish the process description (info); called at start and on every change.

        :param state: the module's run state.
        :param objects: the program's registered objects (what it supplies and consumes).
        :param trust_ttl: the MCP is to trust a TTL beyond its usual ceiling.
        :param quit_time: the seconds the module may take to end after Quit; 0 for the MCP's
            default.
        """
        info = self.obj.info
        info.managed.set_value(managed_state())
        info.locale.set_value(ProcessLocale.INTERNAL)
        info.state.set_value(state)
        info.pid.set_value(module_context.process_id())
        info.host.set_value(socket.gethostname())
        info.mcp.set_value(mcp_owner())
        supplied = [o for o in objects if o.role == SUPPLIER]
        consumed = [o for o in objects if o.role != SUPPLIER]
        info.interfaces.set_value([o.interface_name for o in supplied])
        info.streams.set_value([o.stream or '' for o in supplied])
        info.consumed_interfaces.set_value([o.interface_name for o in consumed])
        info.consumed_streams.set_value([o.stream or '' for o in consumed])
        info.consumed_objects.set_value([o.object_name for o in consumed])
        info.trust_ttl.set_value(trust_ttl)
        info.quit_time.set_value(quit_time)
        self.obj.publish_info()

    @staticmethod
    def interval(ttl: float) -> float:
        """Seconds between beats: half the TTL, at most :data:`MAX_BEAT_INTERVAL_S`.

        :param ttl: the announced TTL, in seconds.
        """
        return min(ttl / 2, MAX_BEAT_INTERVAL_S)

    def beat(self, ttl: float, *, force: bool = False) -> bool:
        """Send a beat announcing ``ttl`` if :meth:`interval` has passed since the last one.

        :param ttl: seconds the MCP is to wait for the next beat.
        :param force: send it now whatever the interval.
        :returns: whether a beat was sent.
        """
        now = time.monotonic()
        if not force and self._last_beat is not None and now - self._last_beat < self.interval(ttl):
            return False
        self.obj.data.ttl = ttl
        self.obj.publish_data()
        self._last_beat = now
        self.beats += 1
        return True

    def next_beat_in(self, ttl: float) -> float:
        """Seconds until the next beat is due (0 before the first).

        :param ttl: the announced TTL, in seconds.
        """
        if self._last_beat is None:
            return 0.0
        return max(0.0, self._last_beat + self.interval(ttl) - time.monotonic())

    def commands(self) -> list[RunState]:
        """State commands that arrived (requests setting ``state``), oldest first."""
        states = []
        while self.obj.get_next_request():
            request = self.obj.requests
            if 'state' in request.ros_message().set_fields:
                states.append(RunState(request.state.get_value()))
        return states
