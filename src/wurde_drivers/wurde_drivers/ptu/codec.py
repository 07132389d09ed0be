"""Codec of the Directed Perception PTU-46 ASCII protocol (docs/protocols.md 2; PTU-D46 manual 4.2-4.5).

Commands are a mnemonic, an optional signed integer and a delimiter (``pp-500 ``); drivers send
them in lower case with a space, as Player's ``ptu46`` does, and numbers are never zero-padded
(Player parses limits with ``strtol(.., 0)``, which would read ``010`` as octal).

Replies end with ``\\r\\n`` and start with ``*`` (success, optionally followed by a space and a
terse value or a verbose sentence) or ``!`` (``! <message>`` error, ``!P``/``!T`` asynchronous
axis-limit hit, ``!T!T!P!P*`` the reset string). With echo on the unit first writes back what it
was sent, so a reply line may begin with the echoed command: :class:`PtuDeframer` cuts that off.

Pure functions over bytes; raises only :class:`~wurde_drivers.errors.CodecError` on bad input.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Literal

from ..errors import CodecError

__all__ = ['Command', 'Error', 'LimitHit', 'Ok', 'PtuDeframer', 'Reply', 'ResetDone', 'RESET_STRING',
           'decode_command', 'decode_commands', 'decode_reply', 'encode_command', 'encode_reply']

#: What the unit prints after a reset: both tilt limits, both pan limits, then success.
RESET_STRING = b'!T!T!P!P*'
#: Longest reply line kept (Player reads into a 255-byte buffer); longer lines are garbage.
MAX_LINE = 255

_MNEMONIC = re.compile(r'[a-z_]{1,4}')
_TOKEN = re.compile(rb'([A-Za-z_]{1,4})([-+]?[0-9]{1,10})?')
_NUMBER = re.compile(r'^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)$')
_WORD_NUMBER = re.compile(r'(?<![\w.])[-+]?[0-9]+(?:\.[0-9]+)?(?![\w.])')
_ECHO = re.compile(rb'^[A-Za-z0-9_ \r\t.+-]*$')


# -- commands (host -> unit) ------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Command:
    """One command: ``name`` (e.g. ``'pp'``) and an optional integer argument.

    A command without a value is a query (``pp``) or an action (``h``, ``ed``).
    """

    name: str
    value: int | None = None


def encode_command(command: Command | str, value: int | None = None) -> bytes:
    """``pp-500 ``: lower case, the value in plain decimal, a space as delimiter.

    :param command: a :class:`Command`, or a mnemonic with ``value`` given separately.
    :param value: the integer argument of a mnemonic; ignored with a :class:`Command`.
    :raises CodecError: a mnemonic that is not 1-4 letters, or a value that is not an int.
    """
    if isinstance(command, Command):
        name, value = command.name, command.value
    else:
        name = command
    name = name.lower()
    if not _MNEMONIC.fullmatch(name):
        raise CodecError(f'PTU command mnemonic must be 1-4 letters: {name!r}')
    if value is None:
        return f'{name} '.encode('ascii')
    if isinstance(value, bool) or not isinstance(value, int):
        raise CodecError(f'PTU command value must be an int: {value!r}')
    return f'{name}{value} '.encode('ascii')


def decode_command(token: bytes) -> Command:
    """One command token as the unit reads it.

    :param token: the token without its delimiter, e.g. ``PP-500`` (any case).
    :raises CodecError: the token is not letters followed by an optional integer.
    """
    match = _TOKEN.fullmatch(token)
    if match is None:
        raise CodecError(f'not a PTU command: {token!r}')
    name = match.group(1).decode('ascii').lower()
    value = int(match.group(2)) if match.group(2) is not None else None
    return Command(name, value)


def decode_commands(data: bytes) -> tuple[list[bytes], bytes]:
    """Split input into complete command tokens (space or CR delimited) and the unfinished rest.

    Empty tokens (a bare delimiter, as Player sends first) are dropped; ``\\n`` counts as a
    delimiter too, so a terminal's CR LF does not make an empty command.

    :param data: the bytes held so far (the previous rest included).
    :returns: the tokens and the bytes after the last delimiter.
    """
    tokens = re.split(rb'[ \r\n\t]', data)
    rest = tokens.pop()
    return [token for token in tokens if token], rest


# -- replies (unit -> host) -------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Ok:
    """``*`` success; ``text`` is what follows ``* `` (a terse value or a verbose sentence)."""

    text: str = ''

    @property
    def number(self) -> float | None:
        """The value: the whole text in terse mode, else the first number in the sentence."""
        if _NUMBER.match(self.text):
            return float(self.text)
        found = _WORD_NUMBER.search(self.text)
        return float(found.group(0)) if found else None


@dataclasses.dataclass(frozen=True)
class Error:
    """``! <message>``: the command was refused (e.g. ``Maximum allowable Pan position is 3090``)."""

    message: str


@dataclasses.dataclass(frozen=True)
class LimitHit:
    """``!P`` or ``!T``: an axis ran into its limit (asynchronous, not a reply to a command)."""

    axis: Literal['pan', 'tilt']


@dataclasses.dataclass(frozen=True)
class ResetDone:
    """``!T!T!P!P*``: the unit recalibrated (the reply to ``r``)."""


Reply = Ok | Error | LimitHit | ResetDone


def _text(raw: bytes, what: str) -> str:
    try:
        text = raw.decode('ascii')
    except UnicodeDecodeError as error:
        raise CodecError(f'PTU {what} is not ASCII: {raw!r}') from error
    if not text or not text.isprintable():
        raise CodecError(f'PTU {what} is empty or not printable: {raw!r}')
    return text


def decode_reply(line: bytes) -> Reply:
    """One reply line.

    :param line: from ``*`` or ``!``; a trailing line end or blanks are dropped.
    :raises CodecError: anything that is not one of the five reply forms.
    """
    line = line.rstrip(b' \r\n')
    if line == b'*':
        return Ok()
    if line == RESET_STRING:
        return ResetDone()
    if line in (b'!P', b'!T'):
        return LimitHit('pan' if line == b'!P' else 'tilt')
    if line.startswith(b'* '):
        return Ok(_text(line[2:].strip(b' '), 'reply'))
    if line.startswith(b'! '):
        return Error(_text(line[2:].strip(b' '), 'error message'))
    raise CodecError(f'not a PTU reply: {line[:40]!r}')


def encode_reply(reply: Reply) -> bytes:
    """The line the unit writes for ``reply``, ending in ``\\r\\n``.

    :param reply: any of the five reply forms.
    :raises CodecError: a text or message that could not be decoded back (not printable ASCII,
        leading or trailing blanks, empty error message).
    """
    if isinstance(reply, ResetDone):
        return RESET_STRING + b'\r\n'
    if isinstance(reply, LimitHit):
        return (b'!P' if reply.axis == 'pan' else b'!T') + b'\r\n'
    if isinstance(reply, Ok):
        if not reply.text:
            return b'*\r\n'
        body, marker = reply.text, b'* '
    elif isinstance(reply, Error):
        body, marker = reply.message, b'! '
    else:
        raise CodecError(f'not a PTU reply: {reply!r}')
    if not body or body != body.strip(' ') or not body.isascii() or not body.isprintable():
        raise CodecError(f'PTU reply text must be printable ASCII without edge blanks: {body!r}')
    return marker + body.encode('ascii') + b'\r\n'


# -- stream -----------------------------------------------------------------------------------
class PtuDeframer:
    """Reply lines out of a byte stream; echo cut off, async limit hits split out, garbage counted.

    A line is cut at ``\\n``; its reply starts at the first ``*`` or ``!``, and what comes before
    must look like an echoed command (letters, digits, blanks, ``-``), else the line is dropped.
    Leading ``!P``/``!T`` that share a line with a reply are returned as separate
    :class:`LimitHit` replies. Lines longer than :data:`MAX_LINE` are dropped.

    Counters: ``replies`` decoded, ``bad_lines`` dropped, ``bytes_skipped`` in dropped lines and
    in echo-only lines (an echoed command whose reply is still to come is not garbage, but its
    bytes are not a reply either).
    """

    def __init__(self) -> None:
        self._buffer = bytearray()
        self._discarding = False
        self.replies = 0
        self.bad_lines = 0
        self.bytes_skipped = 0

    def reset(self) -> None:
        """Forget a partial line (after flushing the port)."""
        self._buffer.clear()
        self._discarding = False

    def feed(self, data: bytes) -> list[Reply]:
        """Every complete reply in ``data`` (with what was buffered before), in order.

        :param data: bytes as read from the line; a partial line is kept for the next call.
        """
        out: list[Reply] = []
        self._buffer += data
        while True:
            end = self._buffer.find(b'\n')
            if end < 0:
                if len(self._buffer) > MAX_LINE:
                    self._drop(len(self._buffer))
                    self._buffer.clear()
                    self._discarding = True
                return out
            line = bytes(self._buffer[:end])
            del self._buffer[:end + 1]
            if self._discarding:            # the tail of an over-long line
                self._discarding = False
                self.bytes_skipped += len(line) + 1
                continue
            if len(line) > MAX_LINE:
                self._drop(len(line) + 1)
                continue
            out.extend(self._line(line))

    def _drop(self, size: int) -> None:
        self.bad_lines += 1
        self.bytes_skipped += size

    def _line(self, line: bytes) -> list[Reply]:
        starts = [i for i in (line.find(b'*'), line.find(b'!')) if i >= 0]
        if not starts:
            if line.strip(b' \r\t'):
                if _ECHO.match(line):       # an echo with no reply on its line
                    self.bytes_skipped += len(line) + 1
                else:
                    self._drop(len(line) + 1)
            return []
        start = min(starts)
        if not _ECHO.match(line[:start]):
            self._drop(len(line) + 1)
            return []
        body = line[start:].rstrip(b' \r')
        replies: list[Reply] = []
        if body != RESET_STRING:
            while body[:2] in (b'!P', b'!T') and body[2:3] in (b'!', b'*', b''):
                replies.append(LimitHit('pan' if body[1:2] == b'P' else 'tilt'))
                body = body[2:]
        if body:
            try:
                replies.append(decode_reply(body))
            except CodecError:
                self._drop(len(line) + 1)
                return []
        self.replies += len(replies)
        return replies
