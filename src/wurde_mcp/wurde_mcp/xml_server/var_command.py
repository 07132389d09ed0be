"""The ``var`` command: get, set and list the variables of a :class:`~.variables.VariablePool`.

AU Robot Servers, "Value exchange", "Full structure", "Set value" and the VAR part of "Online
help".  The reply's tag is the command's own (``<VAR .../>`` answers ``<VAR .../>``).  One plain
get or set answers one line; every other request (several variables, ``list``, a structure,
``allcopy``, ``help``) ends with ``<var info="done"/>``, so that a client knows where it ends.
"""

from __future__ import annotations

import textwrap
from typing import cast

from .command import Attributes, Command, closing, help_block, opening, reply, text
from .session import Session
from .user_vars import UserVariables
from .var_call import call_reply
from .var_log import VarLog
from .variables import VarError, Variable, VariablePool, format_value

__all__ = ['LEGEND', 'VAR_HELP', 'VarCommand']

#: The seed's VAR help, plus AURS's ``copy`` and ``dest=`` (the seed's "Get value to another
#: server").
VAR_HELP = """\
-------------------- Available VAR options:
'variable [variable]*'  Get value of variable(s)
variable="value"        Assign a value to a variable (a new name makes a variable)
list                    Get list of variables in root of variable structure
struct                  Get list of all variables in a structure
[struct.]allCopy        Get list of all variables for var pool copy
struct copy             The same: an xml coded copy of the variables
dest=struct.|var        Where a server receiving the copy puts it (. the root)
desc                    Get variable description too
type=T                  semi-structure where T='pose' | '3d' | 'dq' | 's' | 't'
call='me(par1,par2,..)' Test a method call with name 'me' and some parameters
returnType=[lineseg|3d|pose|...] Expected struct result type of call
log[=false]             Open (or close) the var logfile
log[=false] struct      Start or stop logging of this struct
isLogging   struct      Is this structure beeing logged?
help                    This help message
See also VARPUSH (update event handling)"""

#: The last line of a variable list, as in the seed (no variable here has these properties).
LEGEND = '(H: has time series, L: is logged, R: replay)'

#: Keywords of ``var`` (when written without a value).
FLAGS = frozenset({'help', 'list', 'desc', 'allcopy', 'copy', 'islogging', 'log', 'silent'})
#: Options of ``var`` that take a value (``log`` may have one or not).
OPTIONS = frozenset({'type', 'call', 'returntype', 'log', 'dest'})

_ALLCOPY = '.allcopy'
_NAME_WIDTH = 28        # a list's member column; descriptions start one further (the seed's layout)
_WIDTH = 80


class VarCommand:
    """The ``var`` command handler over one pool, the variables clients make in it and its
    logfile."""

    def __init__(self, pool: VariablePool, user: UserVariables | None = None,
                 log: VarLog | None = None) -> None:
        self._pool = pool
        self._user = user
        self._log = log

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        flags = {key.lower() for key, value in command.args if not value and key.lower() in FLAGS}
        if 'help' in flags:
            return help_block('VAR', VAR_HELP, tag)
        options = {key.lower(): value or '' for key, value in command.args
                   if key.lower() in OPTIONS and (value or key.lower() != 'log')}
        requests = [(key, value) for key, value in command.args
                    if key.lower() not in OPTIONS and (value or key.lower() not in FLAGS)]
        if 'log' in flags or 'log' in options or 'islogging' in flags:
            return self._logging(tag, requests, options.get('log', 'true'), 'islogging' in flags)
        lines: list[str] = []
        if 'call' in options:
            lines += call_reply(tag, options['call'], options.get('returntype', ''))
            if not requests:
                return lines
        copy = flags & {'allcopy', 'copy'}
        extra = [('dest', options['dest'])] if 'dest' in options else []
        single = not flags and len(requests) == 1 and not lines
        if 'list' in flags or not (requests or copy):
            lines += self._listing('', 'desc' in flags)
        elif not requests:
            lines += self._allcopy(tag, '', 'allcopy', extra, 'desc' in flags)
        for key, value in requests:
            if value:
                lines.append(self._set(tag, key, value, options.get('type', 'd')))
                continue
            answer, plain = self._get(tag, key, flags, extra)
            lines += answer
            single = single and plain
        if not single:
            lines.append(reply(tag, [('info', 'done')]))
        return lines

    def _get(self, tag: str, name: str, flags: set[str],
             extra: Attributes = ()) -> tuple[list[str], bool]:
        """The reply to getting ``name`` and whether it is a plain one-line answer."""
        desc = 'desc' in flags
        if name.lower().endswith(_ALLCOPY):
            return self._allcopy(tag, name[:-len(_ALLCOPY)], name, extra, desc), False
        var = self._pool.find(name)
        copy = bool(flags & {'allcopy', 'copy'})
        if var is not None:
            return [self._var_line(tag, var, extra, desc and copy)], not copy
        if self._pool.is_struct(name):
            if copy:
                return self._allcopy(tag, name, name, extra, desc), False
            return self._listing(name, desc), False
        return [reply(tag, [('warning', 'not found - try: var help'), ('name', name)])], True

    def _var_line(self, tag: str, var: Variable, extra: Attributes = (), desc: bool = False) -> str:
        try:
            value = var.current()
            shown, size = format_value(var.typ, value)
        except VarError as exc:
            return reply(tag, [('warning', str(exc)), ('name', var.name)])
        attrs: list[tuple[str, str | None]] = [('name', var.name), ('typ', var.typ), ('size', str(size)),
                                               ('value', shown)]
        if var.typ == 'pose' and len(value) >= 3:
            pose = cast(list[float], value)
            attrs += [(key, format_value('d', [pose[i]])[0]) for i, key in enumerate(('x', 'y', 'th'))]
        attrs += extra
        if desc:
            attrs.append(('desc', var.description))
        return reply(tag, attrs)

    def _set(self, tag: str, name: str, value: str, typ: str = 'd') -> str:
        user = self._user
        if user is not None and (user.owns(name) or self._pool.find(name) is None and
                                 not user.robot_struct(name)):
            return self._make(tag, name, value, typ)
        try:
            old, new = self._pool.set(name, value)
        except VarError as exc:
            var = self._pool.find(name)
            return reply(tag, [('warning', str(exc)), ('name', name if var is None else var.name)])
        var = self._pool.find(name)
        assert var is not None
        shown, size = format_value(var.typ, new)
        return reply(tag, [('name', var.name), ('typ', var.typ), ('size', str(size)),
                           ('value', shown), ('oldValue', format_value(var.typ, old)[0])])

    def _make(self, tag: str, name: str, value: str, typ: str) -> str:
        """A client's variable set, or made by assignment of type ``typ`` (AURS: described
        "new", ``oldValue="(null)"``)."""
        assert self._user is not None
        try:
            old, var = self._user.put(name, typ, value, 'new')
        except VarError as exc:
            return reply(tag, [('warning', str(exc)), ('name', name)])
        shown = '(null)' if old is None else format_value(var.typ, old)[0]
        return self._var_line(tag, var, [('oldValue', shown)])

    def _logging(self, tag: str, requests: list[tuple[str, str | None]], on_text: str,
                 asking: bool) -> list[str]:
        """``log[=false] [names]`` and ``isLogging names``."""
        if self._log is None:
            return [reply(tag, [('warning', 'this server keeps no var logfile')])]
        on = on_text.lower() not in ('false', '0', 'no', 'off')
        if not requests:
            if asking:
                return [reply(tag, [('warning', 'isLogging needs a structure or variable')])]
            try:
                self._log.open() if on else self._log.close()
            except VarError as exc:
                return [reply(tag, [('warning', str(exc))])]
            if not on:
                return [reply(tag, [('info', 'done')])]
            return [reply(tag, [('info', f'Opened logfile ({str(self._log.is_open).lower()}) as '
                                         f'{self._log.path}')])]
        lines = []
        for name, _ in requests:
            var = self._pool.find(name)
            if var is None and not (name.strip('.') and self._pool.is_struct(name)):
                lines.append(reply(tag, [('warning', 'not found - try: var help'), ('name', name)]))
                continue
            what, shown = ('Variable', var.name) if var else ('Struct', self._pool.struct_name(name))
            if asking:
                lines.append(reply(tag, [('info', f'{what} {shown} is logged '
                                                  f'{str(self._log.is_logged(shown)).lower()}')]))
                continue
            try:
                self._log.start(shown, on)
            except VarError as exc:
                lines.append(reply(tag, [('warning', str(exc)), ('name', shown)]))
                continue
            lines.append(reply(tag, [('info', f'{what} {shown} is logged ({str(on).lower()}) to '
                                              f'{self._log.path}, file open '
                                              f'({str(self._log.is_open).lower()})')]))
        return lines

    def _allcopy(self, tag: str, struct: str, asked: str, extra: Attributes = (),
                 desc: bool = False) -> list[str]:
        """One line per variable of ``struct`` ('' the root), or a not-found warning."""
        if struct.strip('.') and not self._pool.is_struct(struct):
            return [reply(tag, [('warning', 'not found - try: var help'), ('name', asked)])]
        return [self._var_line(tag, var, extra, desc)
                for var in self._pool.variables(struct.strip('.'))]

    def _listing(self, struct: str, desc: bool) -> list[str]:
        """The seed's ``<help subject="var list" name="...">`` block of ``struct``'s members;
        a logged variable has an L in its second column (the legend)."""
        root = not struct.strip('.')
        shown = '.' if root else self._pool.struct_name(struct)
        lines = [opening('help', [('subject', 'var list'), ('name', shown)])]
        description = self._pool.description('' if root else shown)
        if description:
            lines.append(text('Description:'.ljust(_NAME_WIDTH + 2) + description))
        for child, is_struct in self._pool.children('' if root else shown):
            full = child if root else f'{shown}.{child}'
            if is_struct:
                member, about = f"  {child}='struct';", self._pool.description(full)
            else:
                var = self._pool.find(full)
                assert var is not None
                logged = self._log is not None and self._log.is_logged(var.name)
                member = f' {"L" if logged else " "}{child}={self._value_text(var)}'
                about = var.description
            lines += [text(line) for line in _with_description(member, about if desc else '')]
        lines += [text(LEGEND), closing('help')]
        return lines

    @staticmethod
    def _value_text(var: Variable) -> str:
        try:
            return format_value(var.typ, var.current())[0]
        except VarError as exc:
            return f'? ({exc})'


def _with_description(member: str, about: str) -> list[str]:
    """``member`` and, from column 29 (or after a longer member), ``about`` wrapped to 80 columns
    (the seed's list layout)."""
    if not about:
        return [member]
    indent = ' ' * (_NAME_WIDTH + 1)
    first, *rest = textwrap.wrap(about, max(30, _WIDTH - max(len(member), _NAME_WIDTH) - 1)) or ['']
    return [member.ljust(_NAME_WIDTH) + ' ' + first] + \
        [indent + line for line in textwrap.wrap(' '.join(rest), _WIDTH - len(indent))]
