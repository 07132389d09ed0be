"""``turn_off [NAME]``: send Quit to a running module, with or without an MCP (guide 7.1).

Every module's heartbeat is a supplier on stream ``heartbeat/<name>`` (see
:mod:`wurde_core.heartbeat`), and a request that sets ``state`` changes the module's run state.
So ``turn_off NAME`` reaches any running module by its CommsManager name:

- when an MCP answers on ``mcp_control`` and its table lists NAME, the MCP is asked to stop it
  (so that it keeps a managed module down instead of restarting it, and escalates to signals
  if the module does not obey).  Where several MCPs share a domain (one per host), it is the
  MCP the module belongs to, as its heartbeat info says (field ``mcp``), from whichever host;
- otherwise — no MCP, or one that does not supervise NAME — Quit goes to NAME's heartbeat
  directly.

Whether an MCP answers is a matter of discovery.  A module an MCP started to keep up says so in
its heartbeat info (managed or critical, from the MCP's configuration): turn_off then waits for
the MCP's control channel as long as for the module.  For any other module it gives an MCP
:data:`MCP_GRACE_S` from its start, and waits as long once the ROS graph shows the MCP's node.

``turn_off`` alone quits every module but the MCP: through the MCP's quit-all when one answers,
else directly to every heartbeat stream in the ROS graph but those of MCPs (a module whose
heartbeat info lists an MCP control stream, under whatever name: one MCP per host).
"""

from __future__ import annotations

import sys
import time
from typing import Any

from wurde_core import CommsManager, ProcessType, RunState, WurdeError, stream_name
from wurde_core.heartbeat import mcp_name
from wurde_core.interfaces import robot_object_class
from wurde_core.mcp_client import CONTROL_STREAM, control_stream
from wurde_core.options import split_ros_arguments

from .control import WAIT_S, connect, read_table, send
from .supervisor import CMD_QUIT_ALL, CMD_STOP

#: How long an MCP may take to be discovered, from the start, when the module itself answers
#: (discovery of two processes can differ by seconds on a loaded machine).
MCP_GRACE_S = 3.0
HEARTBEAT_PREFIX = 'heartbeat/'
MCP_NAME = 'MCP'


def _quit_directly(manager: CommsManager, heartbeat: Any) -> bool:
    """Send Quit on a heartbeat stream; whether the module acknowledged it."""
    heartbeat.requests.state.set_value(RunState.QUIT)
    heartbeat.publish_request()
    return bool(heartbeat.wait_delivered(WAIT_S))


def _heartbeat(manager: CommsManager, name: str) -> Any:
    heartbeat = robot_object_class('Heartbeat')(HEARTBEAT_PREFIX + name)
    manager.register_consumer(heartbeat)
    return heartbeat


def _wait(manager: CommsManager, done: Any, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while not done() and time.monotonic() < deadline:
        manager.step()
        manager.wait(0.02)


def _mcp_seen(manager: CommsManager, mcp: str) -> bool:
    """Whether the ROS graph shows the node of the MCP named ``mcp`` in this namespace (before
    its control channel is matched)."""
    namespace = manager.node.get_namespace()
    return (mcp, namespace) in manager.node.get_node_names_and_namespaces()


def _description(manager: CommsManager, heartbeat: Any) -> tuple[bool, str]:
    """Whether the module's heartbeat info says an MCP started it to keep it up, and the MCP
    it belongs to ('' when none is named); info is transient-local: it comes with the match,
    however late."""
    _wait(manager, lambda: heartbeat.received('info'), WAIT_S)
    managed, owner = None, ''
    while heartbeat.get_next_info():
        managed = heartbeat.info.managed.get_value()
        owner = heartbeat.info.mcp.get_value()
    return managed in (ProcessType.MANAGED, ProcessType.CRITICAL), owner


def _ask_mcp(manager: CommsManager, control: Any, name: str, internal_only: bool = False) -> bool:
    """Ask the MCP on ``control`` to stop ``name`` if its table lists it (``internal_only``: as
    one it started, so surely its own); whether it did."""
    rows = read_table(manager, control, WAIT_S)
    if rows is None or not any(row['name'] == name and (row['locale'] == 'INTERNAL'
                                                        or not internal_only) for row in rows):
        return False
    send(control, CMD_STOP, name)
    control.wait_delivered(WAIT_S)
    print(f'turn_off: asked the MCP on {control.stream} to quit {name}')
    return True


def _one(manager: CommsManager, control: Any, name: str) -> int:
    heartbeat = _heartbeat(manager, name)
    start = time.monotonic()
    _wait(manager, lambda: heartbeat.peers() or control.peers(), WAIT_S)
    if control.peers() and not heartbeat.peers():
        if _ask_mcp(manager, control, name, internal_only=True):  # the MCP at hand started it
            return 0
        _wait(manager, heartbeat.peers, WAIT_S)  # its heartbeat tells whose it is
    if not heartbeat.peers():
        print(f'turn_off: no module {name} answers on {HEARTBEAT_PREFIX}{name}, and no MCP '
              'lists it', file=sys.stderr)
        return 1
    supervised, owner = _description(manager, heartbeat)
    if owner and control.stream != control_stream(owner):
        # It belongs to another MCP (one per host): that one is asked, or it would start the
        # module again.
        manager.unregister(control)
        control = robot_object_class('SimpleControl')(control_stream(owner))
        manager.register_consumer(control)
    if not control.peers():
        if supervised:  # its MCP is there: wait for the control channel
            _wait(manager, control.peers, WAIT_S)
        else:
            mcp = owner or mcp_name()
            _wait(manager, lambda: control.peers() or _mcp_seen(manager, mcp),
                  MCP_GRACE_S - (time.monotonic() - start))
            if _mcp_seen(manager, mcp):
                _wait(manager, control.peers, WAIT_S)
    if control.peers() and _ask_mcp(manager, control, name):
        return 0
    if not _quit_directly(manager, heartbeat):
        print(f'turn_off: {name} did not acknowledge Quit within {WAIT_S:.0f} s', file=sys.stderr)
        return 1
    print(f'turn_off: sent Quit to {name} directly (no MCP supervises it)')
    return 0


def _heartbeat_modules(manager: CommsManager) -> list[str]:
    """Modules with a heartbeat supplier in the ROS graph (the seed's MCP excepted)."""
    names = set()
    for topic_name, _types in manager.node.get_topic_names_and_types():
        try:
            stream, channel = stream_name(topic_name, manager.node.get_namespace())
        except WurdeError:
            continue
        if channel == 'request' and stream.startswith(HEARTBEAT_PREFIX):
            name = stream[len(HEARTBEAT_PREFIX):]
            if name != MCP_NAME and manager.node.count_subscribers(topic_name) > 0:
                names.add(name)
    return sorted(names)


def _is_mcp(manager: CommsManager, heartbeat: Any) -> bool:
    """Whether the module's heartbeat info says it is an MCP (under any name): it supplies an
    MCP control stream.  The info comes with the match, so no later discovery can contradict it."""
    _wait(manager, lambda: heartbeat.received('info'), WAIT_S)
    streams: list[str] = []
    while heartbeat.get_next_info():
        streams = list(heartbeat.info.streams.get_value())
    return any(s == CONTROL_STREAM or s.startswith(CONTROL_STREAM + '/') for s in streams)


def _all(manager: CommsManager, control: Any) -> int:
    _wait(manager, control.peers, WAIT_S)
    if control.peers():
        send(control, CMD_QUIT_ALL)
        control.wait_delivered(WAIT_S)
        print('turn_off: asked the MCP to quit every module')
        return 0
    names = _heartbeat_modules(manager)
    heartbeats = [_heartbeat(manager, name) for name in names]
    for name, heartbeat in zip(names, heartbeats):
        if not heartbeat.wait_for_peers(WAIT_S):
            continue
        if _is_mcp(manager, heartbeat):
            print(f'turn_off: {name} is an MCP: left running')
        elif _quit_directly(manager, heartbeat):
            print(f'turn_off: sent Quit to {name} directly (no MCP answers)')
    if not names:
        print('turn_off: no MCP and no module answers', file=sys.stderr)
        return 1
    return 0


def turn_off(argv: list[str] | None = None) -> int:
    """``turn_off [MODULE]``."""
    args, ros_arguments = split_ros_arguments(list(sys.argv[1:] if argv is None else argv))
    if len(args) > 1:
        print('usage: turn_off [MODULE] [--ros-args -r __ns:=/NAMESPACE]', file=sys.stderr)
        return 2
    manager, control = connect('turnOff', wait_s=0.0, ros_arguments=ros_arguments)
    try:
        return _one(manager, control, args[0]) if args else _all(manager, control)
    finally:
        manager.clean_up()
