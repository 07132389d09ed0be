"""One line of the xmlServer protocol: a client's command parsed, the server's replies formatted.

AU Robot Servers, "Interface description": every command and reply is one line ending in a newline.
A command is a tag (``<var odoPose.pose=""/>``) or, "if you are lazy", the same words without the
brackets (``var odoPose.pose``).  The seed's own examples are not well-formed XML (unquoted values
``<push t=1.5 .../>``, typographic quotes ``<var mappose.pose=””/>``, bare keywords
``<module list/>``), so commands are read by the small tokenizer below, never by an XML parser: it
knows only the five predefined entities and expands them in values only.

Replies go the other way through :func:`reply` (a full tag), :func:`opening`, :func:`closing`,
:func:`text` (a line of a help text) and :func:`help_block`; their values are always quoted and
escaped, so :func:`parse_command` reads back exactly what :func:`reply` wrote.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Sequence

from wurde_idl.errors import WurdeError

__all__ = ['Attributes', 'Command', 'CommandError', 'NAME', 'closing', 'escape', 'help_block',
           'opening', 'parse_command', 'reply', 'text']

#: A tag's attributes in order: (key, value), value None for a bare keyword (``<var list/>``).
Attributes = Sequence[tuple[str, str | None]]

#: A tag or attribute name: ASCII letters, digits and ``_ . : -`` (``odoPose.pose``, ``t``).
NAME = re.compile(r'[A-Za-z0-9_.:\-]+')

#: Characters no line may hold: C0 controls but the tab, DEL and the C1 controls.
_CONTROL = re.compile('[\x00-\x08\x0a-\x1f\x7f-\x9f]')

#: Opening quote -> the characters that close it; typographic quotes close with either of the pair.
_QUOTES = {'"': '"', "'": "'", '\u201c': '\u201c\u201d', '\u201d': '\u201c\u201d',
           '\u2018': '\u2018\u2019', '\u2019': '\u2018\u2019'}

_SPACE = ' \t'

#: The five predefined XML entities, the only ones ever expanded.
_ENTITY = re.compile('&(lt|gt|amp|quot|apos);')
_ENTITY_CHAR = {'lt': '<', 'gt': '>', 'amp': '&', 'quot': '"', 'apos': "'"}

#: The kinds of line: a command (a full tag ``<x .../>`` or a lazy line), a document's opening
#: tag (``<marg name=... version=...>``), its closing tag (``</marg>``) or an XML declaration
#: (``<?xml ...?>``).
KINDS = ('command', 'opening', 'closing', 'declaration')


class CommandError(WurdeError, ValueError):
    """A line that is not a command; ``str()`` is the reason, as the client is told."""


@dataclasses.dataclass(frozen=True)
class Command:
    """One parsed line: the tag as the client spelled it and its attributes in order."""

    #: Tag name, as spelled (``var``, ``VAR``, ``marg``; ``xml`` for a declaration).
    tag: str
    #: (key, value) in order; value None for a bare keyword (``list`` in ``<var list/>``).
    args: list[tuple[str, str | None]] = dataclasses.field(default_factory=list)
    #: One of :data:`KINDS`.
    kind: str = 'command'
    #: Written without brackets (``var odoPose.pose``).
    lazy: bool = False

    @property
    def is_closing(self) -> bool:
        """A closing tag (``</marg>``): the client ends its document."""
        return self.kind == 'closing'

    @property
    def is_opening(self) -> bool:
        """An XML declaration or a document's opening tag (``<marg name=... version=...>``)."""
        return self.kind in ('opening', 'declaration')

    def has(self, key: str) -> bool:
        """Whether attribute ``key`` (any case) is given, with or without a value."""
        key = key.lower()
        return any(k.lower() == key for k, _ in self.args)

    def get(self, key: str) -> str | None:
        """The value of the first attribute ``key`` (any case); None if absent or bare."""
        key = key.lower()
        return next((v for k, v in self.args if k.lower() == key), None)


def parse_command(line: str) -> Command:
    """Parse one command line (its newline may be included).

    :raises CommandError: the line is empty, holds a control character, has an unterminated quote,
        a ``<`` without a tag name, no ``>`` at its end or an unexpected character.
    """
    line = line.rstrip('\r\n')
    bad = _CONTROL.search(line)
    if bad:
        raise CommandError(f'control character 0x{ord(bad.group()):02x} '
                           f'at column {bad.start() + 1}')
    start = len(line) - len(line.lstrip(_SPACE))
    body = line.strip(_SPACE)
    if not body:
        raise CommandError('empty command')
    if not body.startswith('<'):
        tag, args = _Scanner(body, start).tag_and_args('no command keyword')
        return Command(tag, args, 'command', lazy=True)
    if body.startswith('<?'):
        if not body.endswith('?>') or len(body) < 4:
            raise CommandError("an XML declaration must end with '?>'")
        tag, args = _Scanner(body[2:-2], start + 2).tag_and_args("no name after '<?'")
        return Command(tag, args, 'declaration')
    if body.startswith('</'):
        if not body.endswith('>'):
            raise CommandError("no '>' at the end of the closing tag")
        tag, args = _Scanner(body[2:-1], start + 2).tag_and_args("no tag name after '</'")
        if args:
            raise CommandError(f'a closing tag has no attributes: </{tag} {args[0][0]}...>')
        return Command(tag, [], 'closing')
    if not NAME.match(body, 1):
        raise CommandError("no tag name after '<'")
    if body.endswith('/>'):
        inner, kind = body[1:-2], 'command'
    elif body.endswith('>'):
        inner, kind = body[1:-1], 'opening'
    else:
        raise CommandError("no '>' at the end of the tag (or an unterminated quote)")
    tag, args = _Scanner(inner, start + 1).tag_and_args("no tag name after '<'")
    return Command(tag, args, kind)


class _Scanner:
    """The words of one tag's inside (or of a lazy line): a name, then attributes."""

    def __init__(self, text: str, offset: int) -> None:
        self.text = text
        self.pos = 0
        self.offset = offset            # column of text[0] in the line, for the error messages

    def tag_and_args(self, no_tag: str) -> tuple[str, list[tuple[str, str | None]]]:
        tag = self._name()
        if tag is None:
            raise CommandError(no_tag)
        args: list[tuple[str, str | None]] = []
        while True:
            self._skip_space()
            if self.pos >= len(self.text):
                return tag, args
            key = self._name()
            if key is None:
                raise self._unexpected()
            self._skip_space()
            value = None
            if self.pos < len(self.text) and self.text[self.pos] == '=':
                self.pos += 1
                self._skip_space()
                value = self._value(key)
            args.append((key, value))

    def _name(self) -> str | None:
        match = NAME.match(self.text, self.pos)
        if match is None:
            return None
        self.pos = match.end()
        return match.group()

    def _skip_space(self) -> None:
        while self.pos < len(self.text) and self.text[self.pos] in _SPACE:
            self.pos += 1

    def _value(self, key: str) -> str:
        text, pos = self.text, self.pos
        if pos < len(text) and text[pos] in _QUOTES:
            closers = _QUOTES[text[pos]]
            end = pos + 1
            while end < len(text) and text[end] not in closers:
                end += 1
            if end >= len(text):
                raise CommandError(f'unterminated quote in the value of {key} '
                                   f'(column {self.offset + pos + 1})')
            self.pos = end + 1
            return _unescape(text[pos + 1:end])
        end = pos
        while end < len(text) and text[end] not in _SPACE:
            if text[end] in '<>"\'':
                self.pos = end
                raise self._unexpected()
            end += 1
        self.pos = end
        return _unescape(text[pos:end])

    def _unexpected(self) -> CommandError:
        return CommandError(f'unexpected {self.text[self.pos]!r} '
                            f'at column {self.offset + self.pos + 1}')


def _unescape(value: str) -> str:
    if '&' not in value:
        return value
    return _ENTITY.sub(lambda m: _ENTITY_CHAR[m.group(1)], value)


def escape(value: str) -> str:
    """``value`` as an attribute value or text: ``& < > " '`` as entities, control characters (the
    tab excepted) as character references, so that a reply stays one line."""
    value = (value.replace('&', '&amp;').replace('<', '&lt;').replace('>', '&gt;')
             .replace('"', '&quot;').replace("'", '&apos;'))
    return _CONTROL.sub(lambda m: f'&#x{ord(m.group()):x};', value)


def _attributes(tag: str, attrs: Iterable[tuple[str, str | None]]) -> str:
    if not NAME.fullmatch(tag):
        raise ValueError(f'{tag!r} is not a tag name')
    parts = [tag]
    for key, value in attrs:
        if not NAME.fullmatch(key):
            raise ValueError(f'{key!r} is not an attribute name')
        parts.append(key if value is None else f'{key}="{escape(value)}"')
    return ' '.join(parts)


def reply(tag: str, attrs: Iterable[tuple[str, str | None]] = ()) -> str:
    """A full reply tag and its newline: ``<tag key="value" .../>\\n`` (value None: a bare ``key``).

    :raises ValueError: ``tag`` or a key is not a :data:`NAME` (a programming error, not input).
    """
    return f'<{_attributes(tag, attrs)}/>\n'


def opening(tag: str, attrs: Iterable[tuple[str, str | None]] = ()) -> str:
    """An opening tag and its newline: ``<help subject="VAR">\\n``."""
    return f'<{_attributes(tag, attrs)}>\n'


def closing(tag: str) -> str:
    """A closing tag and its newline: ``</help>\\n``."""
    if not NAME.fullmatch(tag):
        raise ValueError(f'{tag!r} is not a tag name')
    return f'</{tag}>\n'


def text(line: str) -> str:
    """One line of text inside a block (a variable list): escaped, and its newline."""
    return escape(line).replace('&quot;', '"').replace('&apos;', "'") + '\n'


def help_block(subject: str, body: str, tag: str, attrs: Attributes = ()) -> list[str]:
    """A help reply as in the seed's "Online help": ``<help subject="...">``, the lines of ``body``
    as they are, ``</help>`` and ``<tag info="done"/>`` (``tag``: the command's own)."""
    lines = [opening('help', [('subject', subject), *attrs])]
    lines.extend(line + '\n' for line in body.splitlines())
    lines += [closing('help'), reply(tag, [('info', 'done')])]
    return lines
