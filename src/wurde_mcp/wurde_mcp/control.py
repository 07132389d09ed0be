"""The seed's mcpController (guide 7.1), and the MCP control channel it shares with turn_off.

Both tools talk to the MCP through the SimpleControl interface on stream ``mcp_control``:
commands go as requests, and the MCP's module table arrives as data (any ROS 2 tool can read it
too, on ``/wurde/mcp_control/data``).  ``turn_off`` lives in :mod:`wurde_mcp.turn_off`.

- ``mcp_controller list`` (or ``status``): the module table (status, managed, state, pid, host, heartbeat age,
  restarts); ``mcp_controller start|stop|restart MODULE``;
  ``mcp_controller state MODULE RUN|IDLE|RESET|RESTART|QUIT``.

Both take ``--ros-args`` (``-r __ns:=/robot1`` reaches the MCP started in ``/robot1``).
``mcp_controller --mcp NAME ...`` reaches the MCP named NAME where several share a domain (one per
host; the default is ``WURDE_MCP_NAME``, else ``MCP``); ``turn_off NAME`` finds the MCP a module
belongs to by itself.
"""

from __future__ import annotations

import sys
import time
from typing import Any

from wurde_core import CommsManager, ProcessLocale, ProcessType, RunState, StatusMode
from wurde_core.heartbeat import mcp_name
from wurde_core.interfaces import robot_object_class
from wurde_core.mcp_client import control_stream
from wurde_core.options import split_ros_arguments

from .supervisor import CMD_RESTART, CMD_START, CMD_STATE, CMD_STOP

WAIT_S = 10.0


def connect(name: str, wait_s: float = WAIT_S, ros_arguments: list[str] | None = None,
            mcp: str | None = None) -> tuple[CommsManager, Any]:
    """A manager with a consumer of an MCP's control stream, once the MCP answers.

    :param name: the manager's (node's) name.
    :param wait_s: how long to wait for the MCP (s); 0 or less: do not wait.
    :param ros_arguments: ROS arguments for the manager (``--ros-args -r __ns:=/robot1`` reaches
        the MCP of that namespace); None: none.
    :param mcp: the MCP's name (None: ``WURDE_MCP_NAME``, else the seed's ``MCP``).
    :returns: the manager and its SimpleControl consumer.
    :raises SystemExit: with a message, when ``wait_s`` is positive and no MCP answers in time.
    """
    manager = CommsManager(name)
    manager.parse_options([name, *(ros_arguments or [])])
    manager.set_no_heartbeat()
    manager.set_no_sleep()
    control = robot_object_class('SimpleControl')(control_stream(mcp or mcp_name()))
    manager.register_consumer(control)
    if wait_s > 0:
        deadline = time.monotonic() + wait_s
        while not control.peers() and time.monotonic() < deadline:
            manager.step()
            manager.wait(0.05)
        if not control.peers():
            manager.clean_up()
            raise SystemExit(f'{name}: no MCP answers on {control.stream} within {wait_s:.0f} s')
    return manager, control


def send(control: Any, command: int, module: str = '', state: RunState = RunState.RUN) -> None:
    """Send one command to the MCP.

    :param control: the SimpleControl consumer from :func:`connect`.
    :param command: ``CMD_START``, ``CMD_STOP``, ``CMD_RESTART`` or ``CMD_STATE`` of
        :mod:`wurde_mcp.supervisor`.
    :param module: the module it is about ('' for none).
    :param state: the run state to set, for ``CMD_STATE``.
    """
    requests = control.requests
    requests.command.set_value(command)
    requests.module.set_value(module)
    requests.state.set_value(state)
    control.publish_request()


def read_table(manager: CommsManager, control: Any,
               wait_s: float = WAIT_S) -> list[dict[str, Any]] | None:
    """The MCP's next module table (it is published at least every half second), or ``None``
    when none arrives within ``wait_s``.

    :param manager: the manager from :func:`connect`, stepped while waiting.
    :param control: its SimpleControl consumer.
    :param wait_s: how long to wait for a table (s).
    :returns: one dict per module: name, status, managed, locale, state (enum names), pid, host,
        age (heartbeat age in s, negative for none) and restarts.
    """
    deadline = time.monotonic() + wait_s
    while time.monotonic() < deadline:
        manager.step()
        if control.get_next_data():
            d = control.data
            return [dict(name=n, status=StatusMode(s).name, managed=ProcessType(m).name,
                         locale=ProcessLocale(w).name, state=RunState(r).name, pid=p, host=h,
                         age=a, restarts=k)
                    for n, s, m, w, r, p, h, a, k in zip(
                        d.module_names, d.module_status, d.module_managed, d.module_locale,
                        d.module_state, d.module_pid, d.module_host, d.module_heartbeat_age,
                        d.module_restarts)]
        manager.wait(0.05)
    return None


def mcp_controller(argv: list[str] | None = None) -> int:
    """``mcp_controller list | status | start M | stop M | restart M | state M STATE``.

    :param argv: the arguments without the program's name, optionally ``--mcp NAME`` first and
        ``--ros-args ...`` last (None: ``sys.argv[1:]``).
    :returns: the exit status: 0, or 2 for a usage error.
    """
    args, ros_arguments = split_ros_arguments(list(sys.argv[1:] if argv is None else argv))
    mcp = None
    if args[:1] == ['--mcp'] and len(args) >= 2:
        mcp, args = args[1], args[2:]
    if args[:1] == ['status']:
        args[0] = 'list'                  # the name a ROS 2 user tries first
    usage = ('usage: mcp_controller [--mcp NAME] list | status | start M | stop M | restart M | '
             'state M STATE')
    commands = {'start': CMD_START, 'stop': CMD_STOP, 'restart': CMD_RESTART}
    if not args or args[0] not in ('list', 'state', *commands) or \
            (args[0] in commands and len(args) != 2) or (args[0] == 'state' and len(args) != 3):
        print(usage, file=sys.stderr)
        return 2
    if args[0] == 'state' and args[2].upper() not in RunState.__members__:
        print(f'mcp_controller: unknown state {args[2]}\n{usage}', file=sys.stderr)
        return 2
    manager, control = connect('mcpController', ros_arguments=ros_arguments, mcp=mcp)
    try:
        if args[0] == 'list':
            rows = read_table(manager, control)
            if rows is None:
                raise SystemExit('mcp_controller: no module table from the MCP')
            print(f'{"module":<20} {"status":<9} {"managed":<10} {"state":<8} {"pid":>7} '
                  f'{"host":<12} {"beat age":>8} {"restarts":>8}')
            for r in rows:
                age = f'{r["age"]:.2f}' if r['age'] >= 0 else '-'
                print(f'{r["name"]:<20} {r["status"]:<9} {r["managed"]:<10} {r["state"]:<8} '
                      f'{r["pid"]:>7} {r["host"]:<12} {age:>8} {r["restarts"]:>8}')
        elif args[0] == 'state':
            send(control, CMD_STATE, args[1], RunState[args[2].upper()])
        else:
            send(control, commands[args[0]], args[1])
        if args[0] != 'list':
            control.wait_delivered(WAIT_S)
            print(f'mcp_controller: sent {" ".join(args)}')
    finally:
        manager.clean_up()
    return 0
