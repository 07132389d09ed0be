"""The seed's MCP tools (guide 7.1): ``turn_off`` and ``mcp_controller``.

Both talk to the MCP through the SimpleControl interface on stream ``mcp_control``: commands go
as requests, and the MCP's module table arrives as data (any ROS 2 tool can read it too, on
``/wurde/mcp_control/data``).

- ``turn_off``: Quit every module but the MCP; ``turn_off MODULE``: Quit that one.
- ``mcp_controller list``: the module table (status, managed, state, pid, host, heartbeat age,
  restarts); ``mcp_controller start|stop|restart MODULE``;
  ``mcp_controller state MODULE RUN|IDLE|RESET|RESTART|QUIT``.
"""

from __future__ import annotations

import sys
import time

from wurde_core import CommsManager, ProcessType, RunState, StatusMode
from wurde_core.interfaces import robot_object_class

from .supervisor import CMD_QUIT_ALL, CMD_RESTART, CMD_START, CMD_STATE, CMD_STOP

WAIT_S = 10.0


def _connect(name: str) -> tuple[CommsManager, object]:
    manager = CommsManager(name)
    manager.set_no_heartbeat()
    manager.set_no_sleep()
    control = robot_object_class('SimpleControl')('mcp_control')
    manager.register_consumer(control)
    deadline = time.monotonic() + WAIT_S
    while not control.peers() and time.monotonic() < deadline:
        manager.step()
        manager.wait(0.05)
    if not control.peers():
        manager.clean_up()
        raise SystemExit(f'{name}: no MCP answers on mcp_control within {WAIT_S:.0f} s')
    return manager, control


def _send(control: object, command: int, module: str = '', state: RunState = RunState.RUN) -> None:
    requests = control.requests  # type: ignore[attr-defined]
    requests.command.set_value(command)
    requests.module.set_value(module)
    requests.state.set_value(state)
    control.publish_request()  # type: ignore[attr-defined]


def _delivered(control: object) -> None:
    """Wait until the MCP acknowledged the request (it is sent at once; this only waits)."""
    control.wait_delivered(WAIT_S)  # type: ignore[attr-defined]


def _table(manager: CommsManager, control: object) -> list[dict[str, object]]:
    deadline = time.monotonic() + WAIT_S
    while time.monotonic() < deadline:
        manager.step()
        if control.get_next_data():  # type: ignore[attr-defined]
            d = control.data  # type: ignore[attr-defined]
            return [dict(name=n, status=StatusMode(s).name, managed=ProcessType(m).name,
                         state=RunState(r).name, pid=p, host=h, age=a, restarts=k)
                    for n, s, m, r, p, h, a, k in zip(
                        d.module_names, d.module_status, d.module_managed, d.module_state,
                        d.module_pid, d.module_host, d.module_heartbeat_age, d.module_restarts)]
        manager.wait(0.05)
    raise SystemExit('mcp_controller: no module table from the MCP')


def turn_off(argv: list[str] | None = None) -> int:
    """``turn_off [MODULE]``."""
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) > 1:
        print('usage: turn_off [MODULE]', file=sys.stderr)
        return 2
    manager, control = _connect('turnOff')
    try:
        if args:
            _send(control, CMD_STOP, args[0])
            print(f'turn_off: asked the MCP to quit {args[0]}')
        else:
            _send(control, CMD_QUIT_ALL)
            print('turn_off: asked the MCP to quit every module')
        _delivered(control)
    finally:
        manager.clean_up()
    return 0


def mcp_controller(argv: list[str] | None = None) -> int:
    """``mcp_controller list | start M | stop M | restart M | state M STATE``."""
    args = list(sys.argv[1:] if argv is None else argv)
    usage = 'usage: mcp_controller list | start M | stop M | restart M | state M STATE'
    commands = {'start': CMD_START, 'stop': CMD_STOP, 'restart': CMD_RESTART}
    if not args or args[0] not in ('list', 'state', *commands) or \
            (args[0] in commands and len(args) != 2) or (args[0] == 'state' and len(args) != 3):
        print(usage, file=sys.stderr)
        return 2
    if args[0] == 'state' and args[2].upper() not in RunState.__members__:
        print(f'mcp_controller: unknown state {args[2]}\n{usage}', file=sys.stderr)
        return 2
    manager, control = _connect('mcpController')
    try:
        if args[0] == 'list':
            rows = _table(manager, control)
            print(f'{"module":<20} {"status":<9} {"managed":<10} {"state":<8} {"pid":>7} '
                  f'{"host":<12} {"beat age":>8} {"restarts":>8}')
            for r in rows:
                age = f'{r["age"]:.2f}' if r['age'] >= 0 else '-'
                print(f'{r["name"]:<20} {r["status"]:<9} {r["managed"]:<10} {r["state"]:<8} '
                      f'{r["pid"]:>7} {r["host"]:<12} {age:>8} {r["restarts"]:>8}')
        elif args[0] == 'state':
            _send(control, CMD_STATE, args[1], RunState[args[2].upper()])
        else:
            _send(control, commands[args[0]], args[1])
        if args[0] != 'list':
            _delivered(control)
            print(f'mcp_controller: sent {" ".join(args)}')
    finally:
        manager.clean_up()
    return 0
