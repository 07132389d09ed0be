"""No client can hurt the xmlServer or its other clients: too many clients, too long lines,
malformed and non-UTF-8 input, a reader that does not read, silent and half-open clients, a
flooding client, a client that vanishes mid-line.  The fixture fails a test whose serve() raised."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading
from collections.abc import Iterator

import pytest
from xml_server_fixture import (DEADLINE, POSE_LINE, RANGES_LINE, Raw, Start, make_pool,
                                wait_until)

from wurde_mcp.xml_server import Variable
from wurde_mcp.xml_server.command import escape

@pytest.fixture
def clients() -> Iterator[list[Raw]]:
    """Raw clients the test opens, closed at its end."""
    opened: list[Raw] = []
    yield opened
    for raw in opened:
        raw.close()


def test_the_eleventh_client_is_told_and_closed(start: Start, clients: list[Raw]) -> None:
    server = start()
    clients += [Raw(server.port) for _ in range(10)]
    wait_until(lambda: server.client_count == 10, 'ten sessions')
    extra = Raw(server.port, greet=False)
    clients.append(extra)
    assert extra.to_eof() == ['<error warning="too many clients: 10 are connected (max 10)"/>']
    for raw in clients[:10]:
        assert raw.ask('var odopose.pose') == POSE_LINE
    stats = server.stats
    assert (stats.accepted, stats.refused) == (10, 1)
    clients[0].ask('q')
    wait_until(lambda: server.client_count == 9, 'a place to free')
    clients.append(Raw(server.port))                   # the place is taken again
    assert clients[-1].ask('var odopose.pose') == POSE_LINE


def test_a_too_long_line_is_dropped_with_a_warning(start: Start, clients: list[Raw]) -> None:
    server = start(max_line=1000)
    raw = Raw(server.port)
    clients.append(raw)
    raw.send(b'<var x="' + b'a' * 3000)                # more than max_line, no newline yet
    assert raw.line() == '<error warning="line longer than 1000 bytes: dropped"/>'
    raw.send(b'a' * 5000 + b'"/>\nvar odopose.pose\n')  # the rest of it, then a command
    assert raw.line() == POSE_LINE
    raw.send(b'var ' + b'b' * 1200 + b'\nvar laser.ranges\n')
    assert raw.line() == '<error warning="line longer than 1000 bytes: dropped"/>'
    assert raw.line() == RANGES_LINE
    stats = server.stats
    assert stats.dropped_long_lines == 2 and stats.lines == 2
    assert stats.peak_input <= 1001


@pytest.mark.parametrize('data, reason', [
    (b'<var a="x/>\n', 'unterminated quote'),
    (b'<\n', "no tag name after '<'"),
    (b'var \x00\x01\n', 'control character 0x00'),
    (b'\xff\xfe<var/>\n', 'no command keyword'),
    (b'<var \xff=""/>\n', 'unexpected'),
    (b'<a/><b/>\n', 'unexpected'),
])
def test_a_malformed_line_is_answered_and_the_session_goes_on(
        start: Start, clients: list[Raw], data: bytes, reason: str) -> None:
    server = start()
    raw = Raw(server.port)
    clients.append(raw)
    raw.send(data)
    answer = raw.line()
    assert answer.startswith('<error warning="malformed command: ') and escape(reason) in answer
    assert raw.ask('var odopose.pose') == POSE_LINE
    assert server.stats.malformed == 1


def test_bad_utf8_in_a_value_is_a_bad_value_not_a_crash(start: Start, clients: list[Raw]) -> None:
    raw = Raw(start().port)
    clients.append(raw)
    raw.send(b'<var drive.speed="\xff\xfe"/>\n')
    assert raw.line() == '<var warning="&quot;\ufffd\ufffd&quot; is not a value of type d" ' \
                         'name="drive.speed"/>'
    assert raw.ask('var odopose.pose') == POSE_LINE


def test_a_reader_that_does_not_read_is_disconnected(start: Start, clients: list[Raw]) -> None:
    pool = make_pool()
    pool.add(Variable('blob.text', 's', '(r) a big string', 'x' * 30000))
    server = start(pool=pool, send_buffer=256 * 1024)
    slow = Raw(server.port, rcvbuf=4096)
    clients.append(slow)
    slow.send(''.join('<push t=0.01 cmd="var blob.text"/>\n' for _ in range(10)))  # 30 MB/s
    wait_until(lambda: server.stats.slow_disconnects == 1, 'the slow reader to be disconnected',
               timeout=20.0)
    assert server.stats.peak_output <= 256 * 1024
    slow.to_eof(timeout=20.0)                          # closed (what was sent, then EOF or reset)
    other = Raw(server.port)
    clients.append(other)
    assert other.ask('var odopose.pose') == POSE_LINE
    assert server.client_count == 1


def test_a_silent_client_is_closed_after_idle_timeout(start: Start, clients: list[Raw]) -> None:
    server = start(idle_timeout=1.0)
    pushed = Raw(server.port)                          # not idle: pushes are sent to it
    clients.append(pushed)
    assert 'added push 1' in pushed.ask('<push t=0.05 cmd="var odopose.pose"/>')
    silent = Raw(server.port)
    clients.append(silent)
    assert silent.to_eof() == ['<error warning="idle for 1 s: closing"/>', '</xmlServer>']
    assert server.stats.idle_disconnects == 1
    pushed.send('var laser.ranges\n')
    assert pushed.until(lambda line: 'laser.ranges' in line)[-1] == RANGES_LINE


def test_silent_clients_do_not_block_a_working_one(start: Start, clients: list[Raw]) -> None:
    server = start(max_clients=11)
    for _ in range(10):                                # connected, greeting unread, half a line
        raw = Raw(server.port, greet=False)
        raw.send('<var odoPose.po')
        clients.append(raw)
    working = Raw(server.port)
    clients.append(working)
    for _ in range(3):
        assert working.ask('var odopose.pose') == POSE_LINE
    assert server.client_count == 11


def test_a_flooding_client_does_not_starve_another(start: Start, clients: list[Raw]) -> None:
    server = start()
    flood, other = Raw(server.port), Raw(server.port)
    clients += [flood, other]
    count = 10000
    answers: list[str] = []

    def drain() -> None:
        with contextlib.suppress(OSError, TimeoutError):
            while len(answers) < count:
                answers.append(flood.line(timeout=30.0))

    reader = threading.Thread(target=drain, daemon=True)
    reader.start()
    sender = threading.Thread(target=flood.send, args=(b'var laser.ranges\n' * count,), daemon=True)
    sender.start()
    wait_until(lambda: len(answers) > 0, 'the flood to be answered')
    assert other.ask('var odopose.pose') == POSE_LINE       # within the deadline, flood or not
    sender.join(30.0)
    reader.join(30.0)
    assert len(answers) == count
    assert set(answers) == {RANGES_LINE}


def test_a_client_that_vanishes_mid_line_is_cleaned_up(start: Start, clients: list[Raw]) -> None:
    server = start()
    half = Raw(server.port)
    half.send('<var odoPose.po')
    half.close()
    reset = Raw(server.port)                           # a reset (SO_LINGER 0) with a push running
    reset.ask('<push t=0.01 cmd="var odopose.pose"/>')
    reset.sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack('ii', 1, 0))
    reset.close()
    wait_until(lambda: server.client_count == 0, 'both sessions to end')
    assert server.stats.lines == 1 and server.stats.malformed == 0
    raw = Raw(server.port)
    clients.append(raw)
    assert raw.ask('var odopose.pose') == POSE_LINE


def test_a_client_that_closes_its_side_gets_its_replies(start: Start, clients: list[Raw]) -> None:
    server = start()
    raw = Raw(server.port)                             # as `printf 'var x\n' | nc -N host port`
    clients.append(raw)
    raw.send('var odopose.pose\nvar laser.ranges\nvar odoPose.po')
    raw.sock.shutdown(socket.SHUT_WR)
    assert raw.to_eof() == [POSE_LINE, RANGES_LINE, '</xmlServer>']
    wait_until(lambda: server.client_count == 0, 'the session to end')


def test_many_bad_lines_in_a_row_keep_the_session(start: Start, clients: list[Raw]) -> None:
    server = start(lines_per_turn=7)
    raw = Raw(server.port)
    clients.append(raw)
    junk = [b'<', b'>', b'</>', b'<?', b'<var', b'"', b'\x00', b'\xc3\x28', b'&amp;', b'<var =1/>',
            b'<var a=1/>', b'   ', b'<!-- x -->', b'<var a="1"', b'push t=1e400 cmd=q']
    raw.send(b'\n'.join(junk) + b'\nvar odopose.pose\n')
    lines = raw.until(lambda line: line == POSE_LINE, timeout=DEADLINE)
    assert len(lines) == len(junk) - 1 + 1             # every line but the blank one is answered
    assert server.stats.malformed == 12
