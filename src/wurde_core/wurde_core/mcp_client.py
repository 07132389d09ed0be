"""The module side of the MCP protocol, over the McpRequest interface on stream ``mcp``
(``mcp/<name>`` for an MCP started as another name: :func:`mcp_stream`).

Seed: WURDE Programming Guide 6.3 and 7 (``-r``, ``-l``).  The MCP supplies ``McpRequest("mcp")``;
each module is a consumer that sends requests and reads the answers from the MCP's info:

- kind 2, report capabilities: ``provided_interfaces``/``provided_streams`` and
  ``consumed_interfaces``/``consumed_objects`` of the module (``-r`` and ``-l``);
- kind 0, assign a stream: ``strategy`` ASSIGNED or AUTO, ``interface``, ``object`` (the alias);
  the MCP answers with the same ``module`` and ``request_id``, ``success`` and ``stream``;
  the request is repeated every :data:`RETRY_S` until answered;
- kind 1, start a module: ``strategy`` NORMAL, ``object`` the stream name wanted.

The client knows nothing of the manager: :meth:`McpClient.poll` returns the assignments it
found, and the manager connects the objects.
"""

from __future__ import annotations

import itertools
import os
import time
from collections.abc import Callable, Sequence
from typing import Any

from .enums import ConnectionStrategy
from .heartbeat import DEFAULT_MCP, mcp_name
from .interfaces import robot_object_class
from .robot_object import SUPPLIER, RobotObject

STREAM = 'mcp'
#: The MCP's control stream (commands from mcp_controller and turn_off, its module table).
CONTROL_STREAM = 'mcp_control'


def mcp_stream(mcp: str = DEFAULT_MCP) -> str:
    """The McpRequest stream of the MCP named ``mcp``: :data:`STREAM` for the seed's MCP, and
    ``mcp/<name>`` for any other, so that several MCPs in one domain (one per host) each answer
    only their own modules.

    :param mcp: the MCP's CommsManager name (default ``MCP``, the seed's).
    """
    return STREAM if mcp == DEFAULT_MCP else f'{STREAM}/{mcp}'


def control_stream(mcp: str = DEFAULT_MCP) -> str:
    """The SimpleControl stream of the MCP named ``mcp`` (its commands and module table):
    :data:`CONTROL_STREAM` for the seed's MCP, ``mcp_control/<name>`` for any other.

    :param mcp: the MCP's CommsManager name (default ``MCP``, the seed's).
    """
    return CONTROL_STREAM if mcp == DEFAULT_MCP else f'{CONTROL_STREAM}/{mcp}'


KIND_ASSIGN, KIND_START, KIND_CAPABILITIES = 0, 1, 2
RETRY_S = 1.0


class McpClient:
    """Sends requests to the MCP and applies its answers."""

    def __init__(self, module: str, warn: Callable[[str], None]) -> None:
        """A consumer of the McpRequest stream of this process's MCP (:func:`mcp_stream`), in
        queue mode; the manager registers it.

        :param module: the module's name, sent in every request.
        :param warn: reports a refused assignment (once per object and reason).
        """
        self.module = module
        self._warn = warn
        self.obj: RobotObject = robot_object_class('McpRequest')(mcp_stream(mcp_name()))
        self.obj._system = True
        self.obj.set_queue_mode(True)
        # Ids differ between incarnations of a module, so that the MCP's last answer to an earlier
        # process of the same name (info is transient-local) is never taken for this one's.
        self._ids = itertools.count((os.getpid() % 100_000) * 20_000 + 1)
        self._pending: dict[int, tuple[RobotObject, float]] = {}
        #: The last refusal told for each object: the same refusal is told once, not every retry
        #: (a module may declare an alias that only some configurations map).
        self._told: dict[int, str] = {}

    def _request(self, kind: int, **values: Any) -> int:
        request_id = next(self._ids)
        requests = self.obj.requests
        requests.request_id.set_value(request_id)
        requests.kind.set_value(kind)
        requests.module.set_value(self.module)
        for name, value in values.items():
            getattr(requests, name).set_value(value)
        self.obj.publish_request()
        return request_id

    @staticmethod
    def capabilities(objects: Sequence[RobotObject]) -> dict[str, list[tuple[str, str]]]:
        """``{'supplies': [(interface, stream)], 'consumes': [(interface, object)]}`` of the
        program's ``objects``.

        :param objects: registered objects; suppliers supply, the others consume (an
            unconnected supplier's stream is ``''``).
        """
        return {
            'supplies': [(o.interface_name, o.stream or '') for o in objects if o.role == SUPPLIER],
            'consumes': [(o.interface_name, o.object_name) for o in objects if o.role != SUPPLIER],
        }

    def report_capabilities(self, objects: Sequence[RobotObject], wait_s: float) -> bool:
        """Send the capability report of ``objects`` (``-r``, ``-l``).

        :param objects: the program's registered objects.
        :param wait_s: seconds to wait, in all, for an MCP to be listening and to acknowledge the
            report (0.5 s more are given to the acknowledgement).
        :returns: whether an MCP received it (its subscription acknowledged it).
        """
        deadline = time.monotonic() + wait_s
        self.obj.wait_for_peers(wait_s)
        caps = self.capabilities(objects)
        self._request(KIND_CAPABILITIES,
                      provided_interfaces=[i for i, _ in caps['supplies']],
                      provided_streams=[s for _, s in caps['supplies']],
                      consumed_interfaces=[i for i, _ in caps['consumes']],
                      consumed_objects=[o for _, o in caps['consumes']])
        if self.obj.peers() == 0:
            return False
        return self.obj.wait_delivered(max(0.0, deadline - time.monotonic()) + 0.5)

    def request_stream(self, obj: RobotObject) -> None:
        """Ask for the stream of an ASSIGNED or AUTO object; :meth:`poll` returns the answer and
        asks again every :data:`RETRY_S` until there is one.

        :param obj: a registered consumer whose strategy is ASSIGNED or AUTO.
        """
        request_id = self._request(KIND_ASSIGN, strategy=obj.strategy,
                                   interface=obj.interface_name, object=obj.object_name)
        self._pending[request_id] = (obj, time.monotonic())

    def request_start(self, obj: RobotObject) -> None:
        """Ask the MCP to start the module that provides a NORMAL object's stream (sent once).

        :param obj: a registered consumer whose strategy is NORMAL.
        """
        self._request(KIND_START, strategy=ConnectionStrategy.NORMAL,
                      interface=obj.interface_name, object=obj.object_name)

    def poll(self) -> list[tuple[RobotObject, str]]:
        """Take in the MCP's answers and repeat unanswered assignment requests; return the
        assignments that arrived, as ``(object, stream)``, for the manager to connect."""
        assigned: list[tuple[RobotObject, str]] = []
        while self.obj.get_next_info():
            info = self.obj.info
            if info.module.get_value() != self.module:
                continue
            entry = self._pending.pop(info.request_id.get_value(), None)
            if entry is None:
                continue
            obj = entry[0]
            if info.success.get_value() and info.stream.get_value():
                assigned.append((obj, info.stream.get_value()))
            else:
                detail = info.detail.get_value() or 'no reason given'
                if self._told.get(id(obj)) != detail:
                    self._told[id(obj)] = detail
                    self._warn(f'MCP could not assign a stream to {obj._label()}: {detail}; '
                               f'asking again every {RETRY_S:g} s')
                self._pending[info.request_id.get_value()] = (obj, time.monotonic())
        now = time.monotonic()
        for request_id, (obj, sent) in list(self._pending.items()):
            if now - sent >= RETRY_S:
                del self._pending[request_id]
                self.request_stream(obj)
        return assigned

    def forget(self, obj: RobotObject) -> None:
        """Stop asking for ``obj``'s stream (it was unregistered).

        :param obj: an object :meth:`request_stream` was called for (any other is ignored).
        """
        self._pending = {k: v for k, v in self._pending.items() if v[0] is not obj}
        self._told.pop(id(obj), None)

    def waiting(self) -> list[RobotObject]:
        """Objects still waiting for their stream."""
        return [obj for obj, _ in self._pending.values()]
