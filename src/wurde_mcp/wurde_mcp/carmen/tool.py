"""``param_tool``: get, set and install the running ``param_daemon``'s parameters (CARMEN's
param_tool), through the client API of :mod:`wurde_core.carmen_param`.

    param_tool [-d DAEMON] get NAME            print "NAME value"
    param_tool [-d DAEMON] set NAME VALUE      VALUE is taken as the type the daemon serves
    param_tool [-d DAEMON] install FILE [ROBOT]   set every parameter of a carmen.ini
    param_tool [-d DAEMON] reread              the daemon re-reads its own carmen.ini

NAME is CARMEN's ``module_variable``.  ``reread`` sets the daemon's ``reread`` parameter to true:
the daemon checks the file while answering (a broken file is refused with file:line: reason,
which this prints) and applies it in its next loop turn.  ``install`` sets each parameter on its
own; the daemon refuses those it does not have (ROS's undeclared-parameter error) or whose type
differs, and the tool reports each and exits 1.  FILE is read by CARMEN's rules
(:mod:`.ini`): what the reader warns about is printed on stderr, file:line: reason; ROBOT is
matched in any case.  Every failure exits 1 with the reason on stderr;
a wrong command line exits 2.
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, WurdeError
from wurde_core.carmen_param import DAEMON, CarmenParams

from .ini import choose_robot, read_ini

__all__ = ['USAGE', 'main']

USAGE = ('usage: param_tool [-d DAEMON] get NAME | set NAME VALUE | install FILE [ROBOT] | reread\n'
         f'  DAEMON defaults to {DAEMON}; NAME is module_variable')

_ARITY = {'get': (1, 1), 'set': (2, 2), 'install': (1, 2), 'reread': (0, 0)}


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv if argv is None else argv)[1:]
    daemon = DAEMON
    if args[:1] == ['-d'] and len(args) > 1:
        daemon, args = args[1], args[2:]
    if args[:1] in (['-h'], ['--help']):
        print(USAGE)
        return 0
    if not args or args[0] not in _ARITY or not (
            _ARITY[args[0]][0] <= len(args) - 1 <= _ARITY[args[0]][1]):
        print(USAGE, file=sys.stderr)
        return 2
    manager = CommsManager('param_tool')   # its node's context is the parameter client's
    manager.set_no_heartbeat()
    params = CarmenParams(manager, daemon)
    try:
        return _run(params, args[0], args[1:])
    except WurdeError as error:
        print(f'param_tool: {error}', file=sys.stderr, flush=True)
        return 1
    finally:
        params.close()
        manager.clean_up()


def _run(params: CarmenParams, command: str, args: list[str]) -> int:
    if command == 'get':
        value = params.get_string(args[0])
        if value is None:
            print(f'param_tool: {params.daemon} has no parameter {args[0]}', file=sys.stderr)
            return 1
        print(f'{args[0]} {value}', flush=True)
    elif command == 'set':
        print(f'{args[0]} {params.set_variable(args[0], args[1])}', flush=True)
    elif command == 'install':
        ini = read_ini(args[0])
        for warning in ini.warnings:
            print(f'param_tool: warning: {warning}', file=sys.stderr, flush=True)
        failed = 0
        for entry in ini.parameters(choose_robot(ini, args[1] if len(args) > 1 else None)).values():
            try:
                params.set_variable(entry.name, entry.value)
            except WurdeError as error:
                print(f'param_tool: {entry.path}:{entry.line}: {error}', file=sys.stderr,
                      flush=True)
                failed += 1
        print(f'param_tool: installed {args[0]}'
              + (f', {failed} refused' if failed else ''), flush=True)
        return 1 if failed else 0
    else:
        params.reread()
        print(f'{params.daemon} re-reads its carmen.ini', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
