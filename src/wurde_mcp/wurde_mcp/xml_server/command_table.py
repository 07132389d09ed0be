"""The xmlServer's commands: registered by name (any case), grouped as ``help`` lists them, and
dispatched (AU Robot Servers, "Interface description": every command has a help option, and an
unknown keyword is answered with a warning in the client's own tag)."""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable, Sequence

from .command import NAME, Command, help_block, reply
from .session import Session

__all__ = ['CommandTable', 'Entry', 'Handler']

_log = logging.getLogger(__name__)

#: A command handler: gets the client's session and the parsed command, returns the reply lines
#: (each ending in a newline; one is added where missing).
Handler = Callable[[Session, Command], Sequence[str]]


@dataclasses.dataclass
class Entry:
    name: str
    handler: Handler
    help_line: str
    help_text: str | None


class CommandTable:
    """The commands of one server."""

    def __init__(self) -> None:
        self._entries: dict[str, Entry] = {}
        self._groups: dict[str, list[str]] = {}

    def __contains__(self, key: object) -> bool:
        """Whether a command is registered under the lower-case ``key``."""
        return key in self._entries

    def add(self, name: str, handler: Handler, help_line: str, *,
            help_text: str | None = None, group: str | None = None) -> None:
        """See :meth:`XmlServer.add_command`.

        :raises ValueError: ``name`` is not a tag name or is taken.
        """
        if not NAME.fullmatch(name):
            raise ValueError(f'{name!r} is not a tag name')
        if name.lower() in self._entries:
            raise ValueError(f'command {name} exists')
        self._entries[name.lower()] = Entry(name, handler, help_line, help_text)
        self._groups.setdefault(group or name.lower(), []).append(name)

    def remove(self, name: str) -> None:
        """Remove command ``name`` (any case; absent: nothing)."""
        entry = self._entries.pop(name.lower(), None)
        for group, names in list(self._groups.items()):
            if entry is not None and entry.name in names:
                names.remove(entry.name)
                if not names:
                    del self._groups[group]

    def groups(self) -> dict[str, list[str]]:
        """The commands by group, as ``help`` lists them (a copy)."""
        return {group: list(names) for group, names in self._groups.items()}

    def help_of(self, name: str) -> Entry | None:
        """The entry of command ``name`` (any case) whose help ``help NAME`` shows."""
        entry = self._entries.get(name.lower())
        return entry if entry is not None and entry.name.lower() != 'help' else None

    def listing(self) -> list[str]:
        """The main help's part on the commands: the groups, then each command's help line."""
        lines = ['- ' + ' '.join(names) for names in self._groups.values()]
        lines.append('All commands has a help option, e.g.:')
        for entry in self._entries.values():
            usage = f'{entry.name} help' if entry.help_text else entry.name
            lines.append(f'{usage:<17} {entry.help_line}')
        return lines

    def dispatch(self, session: Session, command: Command) -> list[str]:
        """The reply lines to ``command``; a closing tag ends the session."""
        entry = self._entries.get(command.tag.lower())
        if command.is_closing:
            session.end()
            return []
        if command.kind == 'declaration' or (command.kind == 'opening' and entry is None):
            return []                    # the client's <?xml ...?> and <marg name=...>
        if entry is None:
            return [reply(command.tag, [('warning', 'Unsupported function keyword')])]
        if [key.lower() for key, value in command.args if not value] == ['help'] \
                and len(command.args) == 1 and entry.name.lower() != 'help':
            return help_block(entry.name.upper(), entry.help_text or entry.help_line, command.tag)
        try:
            lines = entry.handler(session, command)
        except Exception as exc:
            _log.exception('command %r failed', command.tag)
            return [reply(command.tag, [('error', f'{entry.name} failed: {type(exc).__name__}: '
                                                  f'{exc}')])]
        if isinstance(lines, str):
            lines = [lines]
        return [line if line.endswith('\n') else line + '\n' for line in lines or ()]
