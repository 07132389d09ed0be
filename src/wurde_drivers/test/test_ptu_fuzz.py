"""PTU-46 codec fuzzers that reach the reply bodies (issue 10, section 6).

The PTU's frames are lines and carry no checksum, so a corrupted line may well be another valid
reply: every line — a reply with a random body, a valid reply with one byte corrupted, an echoed
command before its reply, junk — must be read as exactly what docs/protocols.md 2 and the deframer's
documented rules make of it, written out here independently:

- a reply is ``*`` | ``* <text>`` | ``! <message>`` | ``!P`` | ``!T`` | ``!T!T!P!P*`` (text and
  message printable ASCII, blanks at their ends dropped);
- a line's reply starts at its first ``*`` or ``!``; what comes before must look like an echoed
  command (letters, digits, blanks, ``.+-_``), else the line is dropped; leading ``!P``/``!T``
  that share a line with a reply are limit hits of their own; a line whose reply is malformed
  gives nothing at all; lines longer than 255 bytes are dropped.

A stream of such lines, cut anywhere, gives exactly the concatenation: nothing spurious.
"""

from __future__ import annotations

import re

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.ptu.codec import (Error, LimitHit, Ok, PtuDeframer, Reply, ResetDone,
                                      decode_reply, encode_reply)

FUZZ = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ECHO = re.compile(rb'[A-Za-z0-9_ \r\t.+-]*')


def printable(text: bytes) -> bool:
    return bool(text) and all(0x20 <= byte <= 0x7E for byte in text)


def expected_reply(line: bytes) -> Reply | None:
    """docs/protocols.md 2's five reply forms (None: not a reply)."""
    line = line.rstrip(b' \r\n')
    if line == b'*':
        return Ok()
    if line == b'!T!T!P!P*':
        return ResetDone()
    if line in (b'!P', b'!T'):
        return LimitHit('pan' if line == b'!P' else 'tilt')
    for marker, kind in ((b'* ', Ok), (b'! ', Error)):
        if line.startswith(marker):
            text = line[2:].strip(b' ')
            return kind(text.decode('ascii')) if printable(text) else None
    return None


def expected_line(line: bytes) -> list[Reply]:
    """What the deframer makes of one line (without its ``\\n``)."""
    if len(line) > 255:
        return []
    starts = [i for i in (line.find(b'*'), line.find(b'!')) if i >= 0]
    if not starts or not ECHO.fullmatch(line[:min(starts)]):
        return []
    body = line[min(starts):].rstrip(b' \r')
    replies: list[Reply] = []
    if body != b'!T!T!P!P*':
        while body[:2] in (b'!P', b'!T') and body[2:3] in (b'!', b'*', b''):
            replies.append(LimitHit('pan' if body[1:2] == b'P' else 'tilt'))
            body = body[2:]
    if body:
        reply = expected_reply(body)
        if reply is None:
            return []
        replies.append(reply)
    return replies


_TEXT = st.binary(max_size=40).map(lambda b: b.replace(b'\n', b'.'))
_WORDS = st.text(st.characters(min_codepoint=0x20, max_codepoint=0x7E), max_size=40).map(
    lambda t: t.encode('ascii'))
ECHOES = st.sampled_from([b'', b'PP ', b'pp-500 ', b'PR ', b'TP604 ', b'ft ', b'x*'])


@st.composite
def lines(draw: st.DrawFn) -> bytes:
    """One line (no ``\\n``): a reply with a random body, a valid reply corrupted in one byte,
    limit hits before a reply, an echo before any of them, or junk."""
    kind = draw(st.sampled_from(['body', 'body', 'corrupted', 'limits', 'junk']))
    if kind == 'body':
        line = draw(st.sampled_from([b'* ', b'! ', b'*', b'!'])) + draw(st.one_of(_WORDS, _TEXT))
    elif kind == 'limits':
        line = draw(st.sampled_from([b'!P', b'!T', b'!P!T'])) + draw(st.sampled_from(
            [b'', b'*', b'* 12', b'! Illegal Command', b'!T!P*', b'x']))
    elif kind == 'junk':
        line = draw(_TEXT)
    else:
        valid = encode_reply(draw(st.sampled_from([
            Ok(), Ok('0'), Ok('185.1428'), Ok('Current Pan position is -500'),
            Error('Maximum allowable Pan position is 3090'), LimitHit('pan'), ResetDone()])))
        valid = valid.rstrip(b'\r\n')
        index = draw(st.integers(0, len(valid) - 1))
        value = draw(st.integers(0, 255).filter(lambda v: v not in (valid[index], 0x0A)))
        line = valid[:index] + bytes((value,)) + valid[index + 1:]
    return draw(ECHOES) + line + draw(st.sampled_from([b'\r', b'', b' \r']))


@FUZZ
@given(st.sampled_from([b'* ', b'! ', b'*', b'!']), st.one_of(_WORDS, _TEXT))
def test_a_reply_with_a_random_body_decodes_to_what_it_says(marker: bytes, body: bytes) -> None:
    line = marker + body + b'\r\n'
    want = expected_reply(line)
    event('refused' if want is None else type(want).__name__)
    if want is None:
        with pytest.raises(CodecError):
            decode_reply(line)
    else:
        assert decode_reply(line) == want


@FUZZ
@given(lines())
def test_a_line_gives_exactly_the_replies_it_holds(line: bytes) -> None:
    want = expected_line(line)
    event(f'{len(want)} replies')
    assert PtuDeframer().feed(line + b'\n') == want


@FUZZ
@given(st.lists(lines(), max_size=10), st.lists(st.integers(1, 64), min_size=1, max_size=10))
def test_a_stream_gives_exactly_what_its_lines_hold(items: list[bytes], cuts: list[int]) -> None:
    stream = b''.join(line + b'\n' for line in items)
    deframer = PtuDeframer()
    got: list[Reply] = []
    position, index = 0, 0
    while position < len(stream):
        size = cuts[index % len(cuts)]
        got += deframer.feed(stream[position:position + size])
        position, index = position + size, index + 1
    assert got == [reply for line in items for reply in expected_line(line)]
    assert deframer.replies == len(got)
