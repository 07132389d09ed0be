"""The ``var`` command: get, set and list the variables of a :class:`~.variables.VariablePool`.

AU Robot Servers, "Value exchange", "Full structure", "Set value" and the VAR part of "Online
help".  The reply's tag is the command's own (``<VAR .../>`` answers ``<VAR .../>``).  One plain
get or set answers one line; every other request (several variables, ``list``, a structure,
``allcopy``, ``help``) ends with ``<var info="done"/>``, so that a client knows where it ends.
"""

from __future__ import annotations

import textwrap

from .command import Command, closing, help_block, opening, reply, text
from .session import Session
from .variables import VarError, Variable, VariablePool, format_value

__all__ = ['LEGEND', 'VAR_HELP', 'VarCommand']

#: The seed's VAR help, without the options this server does not have (type, call, returnType,
#: log, isLogging).
VAR_HELP = """\
-------------------- Available VAR options:
'variable [variable]*'  Get value of variable(s)
variable="value"        Assign a value to a variable
list                    Get list of variables in root of variable structure
struct                  Get list of all variables in a structure
[struct.]allCopy        Get list of all variables for var pool copy
desc                    Get variable description too
help                    This help message
See also VARPUSH (update event handling)"""

#: The last line of a variable list, as in the seed (no variable here has these properties).
LEGEND = '(H: has time series, L: is logged, R: replay)'

#: Keywords of ``var`` (when written without a value).
FLAGS = frozenset({'help', 'list', 'desc', 'allcopy'})

_ALLCOPY = '.allcopy'
_NAME_WIDTH = 28        # a list's member column; descriptions start one further (the seed's layout)
_WIDTH = 80


class VarCommand:
    """The ``var`` command handler over one pool."""

    def __init__(self, pool: VariablePool) -> None:
        self._pool = pool

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        flags = {key.lower() for key, value in command.args if not value and key.lower() in FLAGS}
        if 'help' in flags:
            return help_block('VAR', VAR_HELP, tag)
        requests = [(key, value) for key, value in command.args
                    if value or key.lower() not in FLAGS]
        lines: list[str] = []
        single = not flags and len(requests) == 1
        if 'list' in flags or not (requests or flags & {'allcopy'}):
            lines += self._listing('', 'desc' in flags)
        elif not requests:
            lines += self._allcopy(tag, '', 'allcopy')
        for key, value in requests:
            if value:
                lines.append(self._set(tag, key, value))
                continue
            answer, plain = self._get(tag, key, flags)
            lines += answer
            single = single and plain
        if not single:
            lines.append(reply(tag, [('info', 'done')]))
        return lines

    def _get(self, tag: str, name: str, flags: set[str]) -> tuple[list[str], bool]:
        """The reply to getting ``name`` and whether it is a plain one-line answer."""
        if name.lower().endswith(_ALLCOPY):
            return self._allcopy(tag, name[:-len(_ALLCOPY)], name), False
        var = self._pool.find(name)
        if var is not None:
            return [self._var_line(tag, var)], True
        if self._pool.is_struct(name):
            if 'allcopy' in flags:
                return self._allcopy(tag, name, name), False
            return self._listing(name, 'desc' in flags), False
        return [reply(tag, [('warning', 'not found - try: var help'), ('name', name)])], True

    def _var_line(self, tag: str, var: Variable) -> str:
        try:
            value = var.current()
            shown, size = format_value(var.typ, value)
        except VarError as exc:
            return reply(tag, [('warning', str(exc)), ('name', var.name)])
        attrs = [('name', var.name), ('typ', var.typ), ('size', str(size)), ('value', shown)]
        if var.typ == 'pose' and len(value) >= 3:
            attrs += [(key, format_value('d', [value[i]])[0])          # type: ignore[list-item]
                      for i, key in enumerate(('x', 'y', 'th'))]
        return reply(tag, attrs)

    def _set(self, tag: str, name: str, value: str) -> str:
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

    def _allcopy(self, tag: str, struct: str, asked: str) -> list[str]:
        """One line per variable of ``struct`` ('' the root), or a not-found warning."""
        if struct.strip('.') and not self._pool.is_struct(struct):
            return [reply(tag, [('warning', 'not found - try: var help'), ('name', asked)])]
        return [self._var_line(tag, var) for var in self._pool.variables(struct.strip('.'))]

    def _listing(self, struct: str, desc: bool) -> list[str]:
        """The seed's ``<help subject="var list" name="...">`` block of ``struct``'s members."""
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
                member, about = f'  {child}={self._value_text(var)}', var.description
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
