"""The PTU-46 codec: golden lines from docs/protocols.md 2 and the manual, fuzzing, the deframer."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.ptu.codec import (RESET_STRING, Command, Error, LimitHit, Ok, PtuDeframer,
                                      ResetDone, decode_command, decode_commands, decode_reply,
                                      encode_command, encode_reply)


# -- golden -----------------------------------------------------------------------------------
def test_player_init_sequence_bytes() -> None:
    # Player ptu46.cc sends " ", "ft ", "ed ", "ci ", "i " (docs/protocols.md 2).
    assert [encode_command(name) for name in ('ft', 'ed', 'ci', 'i')] == \
        [b'ft ', b'ed ', b'ci ', b'i ']
    assert encode_command('PR') == b'pr '          # drivers send lower case


def test_numbers_are_never_zero_padded() -> None:
    assert encode_command('pp', 7) == b'pp7 '
    assert encode_command('pp', -500) == b'pp-500 '
    assert encode_command(Command('ps', 0)) == b'ps0 '
    assert encode_command('tp', 604) == b'tp604 '


def test_bad_commands_are_refused() -> None:
    for name in ('', 'p1', 'toolong', 'p p'):
        with pytest.raises(CodecError):
            encode_command(name)
    with pytest.raises(CodecError):
        encode_command('pp', 1.5)  # type: ignore[arg-type]
    with pytest.raises(CodecError):
        encode_command('pp', True)


@pytest.mark.parametrize('line, reply', [
    (b'*', Ok()),
    (b'* 0', Ok('0')),
    (b'* 185.1428', Ok('185.1428')),
    (b'* Current Pan position is 0', Ok('Current Pan position is 0')),
    (b'! Maximum allowable Pan position is 3090', Error('Maximum allowable Pan position is 3090')),
    (b'!P', LimitHit('pan')),
    (b'!T', LimitHit('tilt')),
    (b'!T!T!P!P*', ResetDone()),
])
def test_golden_replies(line: bytes, reply: object) -> None:
    assert decode_reply(line) == reply
    assert decode_reply(line + b'\r\n') == reply
    assert encode_reply(reply) == line + b'\r\n'  # type: ignore[arg-type]


def test_values_of_terse_and_verbose_replies() -> None:
    assert Ok('185.1428').number == pytest.approx(185.1428)
    assert Ok('-3090').number == -3090
    assert Ok('Current Pan position is -500').number == -500
    assert Ok('185.1428 seconds arc per Pan position').number == pytest.approx(185.1428)
    assert Ok('Maximum Pan speed is 2902 positions/sec').number == 2902
    assert Ok('Pan acceleration is 2000 positions/sec^2').number == 2000
    assert Ok('i').number is None
    assert Ok().number is None


@pytest.mark.parametrize('line', [b'', b'x', b'*x', b'* \t', b'!', b'! ', b'!X', b'!PP', b'* \xff',
                                  b'! \x01', b'!T!T!P!P', b'+ 1'])
def test_other_lines_are_codec_errors(line: bytes) -> None:
    with pytest.raises(CodecError):
        decode_reply(line)


def test_command_tokens_as_the_unit_reads_them() -> None:
    assert decode_command(b'PP-500') == Command('pp', -500)
    assert decode_command(b'ft') == Command('ft')
    assert decode_command(b'ps+10') == Command('ps', 10)
    for token in (b'', b'12', b'pp1x', b'pp--1', b'p\xff'):
        with pytest.raises(CodecError):
            decode_command(token)
    tokens, rest = decode_commands(b' ft ed\rci\r\ni pp10')
    assert tokens == [b'ft', b'ed', b'ci', b'i'] and rest == b'pp10'


# -- deframer -----------------------------------------------------------------------------------
def test_echoed_replies_are_cut_after_the_echo() -> None:
    deframer = PtuDeframer()
    # The manual's examples with echo on: "PP * 0", "PP3200 ! Maximum ...", CR as delimiter.
    replies = deframer.feed(b'PP * 0\r\nPP3200 ! Maximum allowable Pan position is 3090\r\n'
                            b'pp\r* 22\r\n r !T!T!P!P*\r\n')
    assert replies == [Ok('0'), Error('Maximum allowable Pan position is 3090'), Ok('22'),
                       ResetDone()]
    assert deframer.bad_lines == 0


def test_limit_hits_sharing_a_line_are_split_out() -> None:
    deframer = PtuDeframer()
    assert deframer.feed(b'!P* 22\r\n!T!P\r\n') == [LimitHit('pan'), Ok('22'), LimitHit('tilt'),
                                                    LimitHit('pan')]
    assert deframer.feed(RESET_STRING + b'\r\n') == [ResetDone()]


def test_garbage_lines_are_dropped_and_counted() -> None:
    deframer = PtuDeframer()
    replies = deframer.feed(b'\x93\xfe*\x00\r\n* 1\r\n' + b'z' * 300 + b'\r\n* 2\r\n#? * 3\r\n*\r\n')
    assert replies == [Ok('1'), Ok('2'), Ok()]
    assert deframer.bad_lines == 3
    assert deframer.bytes_skipped >= 300


def test_partial_lines_wait_for_their_end() -> None:
    deframer = PtuDeframer()
    assert deframer.feed(b'* Current Pan pos') == []
    assert deframer.feed(b'ition is 12\r') == []
    assert deframer.feed(b'\n') == [Ok('Current Pan position is 12')]


# -- fuzz -----------------------------------------------------------------------------------------
_TEXT = st.text(st.characters(min_codepoint=0x21, max_codepoint=0x7E), min_size=1, max_size=30)
_REPLIES = st.one_of(
    st.builds(Ok, st.one_of(st.just(''), _TEXT)),
    st.builds(Error, _TEXT),
    st.builds(LimitHit, st.sampled_from(['pan', 'tilt'])),
    st.just(ResetDone()))


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=80))
def test_fuzz_decode_reply_returns_a_reply_or_codec_error(data: bytes) -> None:
    try:
        reply = decode_reply(data)
    except CodecError:
        return
    assert isinstance(reply, (Ok, Error, LimitHit, ResetDone))


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=80))
def test_fuzz_decode_command_returns_a_command_or_codec_error(data: bytes) -> None:
    try:
        command = decode_command(data)
    except CodecError:
        return
    assert decode_command(encode_command(command).rstrip(b' ')) == command


@settings(max_examples=300, deadline=None)
@given(_REPLIES)
def test_fuzz_encode_then_decode_gives_the_reply_back(reply: object) -> None:
    line = encode_reply(reply)  # type: ignore[arg-type]
    assert decode_reply(line) == reply
    assert PtuDeframer().feed(line) == [reply]


@settings(max_examples=300, deadline=None)
@given(st.from_regex(r'[a-z]{1,4}', fullmatch=True),
       st.one_of(st.none(), st.integers(-10**9, 10**9)))
def test_fuzz_commands_round_trip(name: str, value: int | None) -> None:
    encoded = encode_command(name, value)
    assert not encoded.startswith(b'0') and b' 0' not in encoded
    tokens, rest = decode_commands(encoded)
    assert rest == b'' and [decode_command(token) for token in tokens] == [Command(name, value)]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.binary(max_size=40), st.lists(_REPLIES, max_size=3)), max_size=6),
       st.data())
def test_fuzz_stream_recovers_every_reply_after_garbage(parts: list, data: st.DataObject) -> None:
    stream = b''
    expected = []
    for garbage, replies in parts:
        stream += garbage + b'\r\n'
        for reply in replies:
            stream += encode_reply(reply)
            expected.append(reply)
    deframer = PtuDeframer()
    got = []
    position = 0
    while position < len(stream):
        size = data.draw(st.integers(1, 64))
        got.extend(deframer.feed(stream[position:position + size]))
        position += size
    remaining = iter(got)
    assert all(any(reply == candidate for candidate in remaining) for reply in expected), \
        (expected, got)
