"""The server core's commands ``module``, ``alive``, ``ping`` and ``shelp`` (AU Robot Servers,
"Online help": ``- push q server help shelp module do BASH alive quit exit``; ``(ping
[tod=sss.usec] Time difference analysis (TCP only))``).

Answered as AURS's server core answers them: ``alive`` with ``<alive last="0.010234"/>`` (seconds
since the server's previous loop turn), ``ping [tod=...]`` with the server's time of day and, when
the client gave its own, ``clientToServerSec``, ``shelp`` as ``help``.  ``module list`` lists this
server's modules (its command groups) in AURS's layout, ``module load=odoPose|utmPose|mapPose``
finds them loaded already (they are built in), ``module load=if alias=X`` adds an interface to
another server (:mod:`.interface`) and ``module unload=X`` removes it; no other module can be
loaded: this server has no plug-ins.  ``do`` and ``BASH`` (a shell command from the socket) are left
out on purpose.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from .command import NAME, Command, escape, help_block, reply
from .host import ServerHost
from .interface import IF_NAME, InterfaceModule
from .session import Session

__all__ = ['ALIVE_HELP', 'MODULE_HELP', 'PING_HELP', 'ModuleCommand', 'alive', 'ping']

#: The modules built in, as ``module load=`` names them.
STATIC = ('odoPose', 'utmPose', 'mapPose')

MODULE_HELP = ('----- Available MODULE options:\n'
               'list               List current modules\n'
               'reslist            List current resources (the root structures)\n'
               "load='odoPose'    Load odometry pose history resource (built in)\n"
               "load='utmPose'    Load GPS based UTM pose history resource (built in)\n"
               "load='mapPose'    Load map pose history resource (built in)\n"
               "load=if alias=X    Load an interface to another server as command X\n"
               "unload='X'         Unload the interface X\n"
               'help               Show this list\n'
               '---')

ALIVE_HELP = ('Alive returns number of seconds since last server thread loop\n'
              'this should not exceed the maximum command time,\n'
              'and this should not (normally) exceed 1 second.\n'
              'help           This help text\n'
              '---')

PING_HELP = ('tod=sss.usec    The client\'s time of day: the reply gives clientToServerSec\n'
             'The reply\'s tod is the server\'s time of day (TCP only)')


def alive(server: ServerHost) -> Callable[[Session, Command], list[str]]:
    """The ``alive`` handler of ``server``."""
    def handler(client: Session, command: Command) -> list[str]:
        return [reply(command.tag, [('last', f'{server.turn_gap:f}')])]
    return handler


def _tod(seconds: float) -> str:
    whole = int(seconds)
    return f'{whole}.{min(999_999, round((seconds - whole) * 1e6)):06d}'


def ping(client: Session, command: Command) -> list[str]:
    """``ping [tod=sss.usec]``: the server's time and the delay since the client's."""
    now = time.time()
    attrs = [('tod', _tod(now))]
    given = command.get('tod')
    if given is not None:
        try:
            attrs.append(('clientToServerSec', f'{now - float(given):8.6f}'))
        except ValueError:
            return [reply(command.tag, [('warning', f'tod="{given}" is not sss.usec')])]
    return [reply(command.tag, attrs)]


class ModuleCommand:
    """The ``module`` handler: lists the server's modules, loads and unloads interfaces."""

    def __init__(self, server: ServerHost) -> None:
        self._server = server
        self._interfaces: dict[str, InterfaceModule] = {}

    @property
    def interfaces(self) -> dict[str, InterfaceModule]:
        """The loaded interfaces by alias (lower case)."""
        return self._interfaces

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        known = {'load', 'alias', 'unload', 'list', 'reslist', 'help'}
        unknown = [f" {key}='{value or ''}'" for key, value in command.args
                   if key.lower() not in known]
        if unknown:
            return [reply(tag, [('warning', f'unused options {"".join(unknown)}')])]
        if not command.args or command.has('help'):
            return help_block('module help', MODULE_HELP, tag)
        if command.has('list'):
            return help_block(f'{tag} list', self._list(command.has('reslist')), tag)
        if command.has('reslist'):
            return help_block(f'{tag} resource list', self._resources(), tag)
        if command.get('load'):
            return [self.load(command.get('load') or '', command.get('alias') or '', tag)]
        if command.get('unload'):
            return [self._unload(tag, command.get('unload') or '')]
        return [reply(tag, [('warning', 'Unsupported option')])]

    def _list(self, resources: bool) -> str:
        s = self._server.settings
        groups = self._server.command_groups()
        lines = [f"Module core '{s.name}-{s.version}'",
                 f"      Handles: {' '.join(groups.pop('server', []))}"]
        for number, (group, names) in enumerate(groups.items(), start=1):
            interface = self._interfaces.get(group.lower())
            title = f'{interface.alias} a {IF_NAME}' if interface else group
            lines += [f'Module {number} {title}', f"      Handles: {' '.join(names)}"]
        if resources:
            lines.append(self._resources())
        return '\n'.join(lines)

    def _resources(self) -> str:
        pool = self._server.pool
        return '\n'.join(f'{name} ({"struct" if is_struct else "variable"})'
                         for name, is_struct in pool.children('')) or 'no resources'

    def load(self, name: str, alias: str = '', tag: str = 'module') -> str:
        """``module load=NAME alias=ALIAS``: its reply line (a warning when it cannot be)."""
        if name.lower() in (m.lower() for m in STATIC):
            return reply(tag, [('info', 'done')])
        if name.lower() != 'if':
            return reply(tag, [('warning', f'Module load error: {escape(name)}: this server loads '
                                           f'no plug-ins (only {", ".join(STATIC)} and if)')])
        alias = alias or 'if'
        if not NAME.fullmatch(alias) or '.' in alias or ':' in alias:
            return reply(tag, [('warning', f'alias={alias} is not a command name')])
        interface = InterfaceModule(self._server, alias)
        try:
            interface.install()
        except ValueError:
            return reply(tag, [('warning', f'alias={alias}: a command of that name exists')])
        self._interfaces[alias.lower()] = interface
        return reply(tag, [('info', 'done')])

    def _unload(self, tag: str, alias: str) -> str:
        interface = self._interfaces.pop(alias.lower(), None)
        if interface is None:
            return reply(tag, [('warning', 'Unload failed - use index, filename or first part of '
                                           'name (only a loaded if module can be unloaded)')])
        interface.uninstall()
        return reply(tag, [('info', 'done')])

    def close(self) -> None:
        """Hang up every interface (the server is closing)."""
        for interface in self._interfaces.values():
            interface.hang_up()
