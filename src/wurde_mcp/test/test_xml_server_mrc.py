"""Mobotware's robot controller ``mrc`` as a client: its exact bytes (the XML declaration,
``<smrdemo version="2.00" >``, then one ``<pt tod=.. x=.. y=".. " th=".. " />`` per 100 Hz tick) are
taken as AURS takes them — the pose becomes ``odoPose.pose`` — and never answered; an hour of them
through the real ``xml_server`` gets no reply and its memory stays flat."""

from __future__ import annotations

import pathlib
import re
import time
from collections.abc import Iterator

import pytest
from wurde_testing import ChildProcess, find_executable
from xml_server_fixture import Raw, Start

from wurde_mcp.xml_server.command import parse_command
from wurde_mcp.xml_server.pose_command import PoseError, parse_pose

#: What mrc's serverconnect() sends first, byte for byte.
MRC_HELLO = b'<?xml version="1.0" encoding="UTF-8"?>\n<smrdemo version="2.00" >\n'
#: An hour of mrc's control ticks at 100 Hz.
HOUR = 360_000
#: Ticks before memory is first measured: six minutes, so that every buffer has its size.
WARM_UP = 36_000
#: Most the server's resident memory may grow over the other 54 minutes (bytes).  A pose kept per
#: line would be tens of MB; what stays is the allocator's noise.
FLAT = 2 << 20
#: Longest wait for the server to come up, or to answer after the flood (a loaded machine).
DEADLINE = 120.0


def pt(tick: int) -> str:
    """mrc's line for control tick ``tick``, formatted as mrc formats it (printf
    ``<pt tod="%ld.%06ld" x="%.4f" y="%.4f " th="%.4f " />``)."""
    sec, usec = 1286376207 + tick // 100, (tick % 100) * 10_000
    return (f'<pt tod="{sec}.{usec:06d}" x="{tick * 1e-4:.4f}" y="{-tick * 2e-4:.4f} " '
            f'th="{(tick % 600) / 200 - 1.5:.4f} " />\n')


def pose_reply(tick: int) -> str:
    """``var odoPose.pose``'s reply once tick ``tick`` was the newest pose."""
    found = re.fullmatch(r'<pt tod="(\S+)" x="(\S+)" y="(\S+) " th="(\S+) " />\n', pt(tick))
    assert found is not None
    tod, x, y, th = (float(v) for v in found.groups())

    def number(v: float) -> str:
        return f'{v:.6f}'.rstrip('0').rstrip('.') if abs(v) >= 1e6 else f'{v:.10g}'

    value = ' '.join(number(v) for v in (x, y, th, tod))
    return (f'<var name="odoPose.pose" typ="pose" size="4" value="{value}" x="{number(x)}" '
            f'y="{number(y)}" th="{number(th)}"/>')


@pytest.fixture
def clients() -> Iterator[list[Raw]]:
    opened: list[Raw] = []
    yield opened
    for raw in opened:
        raw.close()


@pytest.mark.parametrize('line, pose', [
    (pt(123).strip(), (0.0123, -0.0246, -0.885, 1286376208.23)),
    ('<pt tod="5.5" x=" 1 " y="2" h="0.5"/>', (1.0, 2.0, 0.5, 5.5)),        # AURS also takes h=
    ('<pt tod="1.0" x="1" y="2" th="3" vel="0.4" q="2.0"/>', (1.0, 2.0, 3.0, 1.0)),
])
def test_a_pose_line_parses(line: str, pose: tuple[float, ...]) -> None:
    assert parse_pose(parse_command(line)) == pytest.approx(pose)


@pytest.mark.parametrize('line, reason', [
    ('<pt x="1" y="2" th="3"/>', 'a pose needs tod='),
    ('<pt tod="1" x="1" y="2"/>', 'a pose needs th/h='),
    ('<pt tod="1" x="one" y="2" th="3"/>', 'x="one" is not a number'),
    ('<pt tod="1" x="nan" y="2" th="3"/>', 'x="nan" is not a finite number'),
])
def test_a_line_that_is_no_pose_is_refused_with_its_reason(line: str, reason: str) -> None:
    with pytest.raises(PoseError, match=re.escape(reason)):
        parse_pose(parse_command(line))


def test_mrc_s_poses_set_odopose_without_a_reply(start: Start, clients: list[Raw]) -> None:
    """The pose goes through the variables: a get reads it, a varpush of another client runs."""
    server = start()
    watcher, mrc = Raw(server.port), Raw(server.port)
    clients += [watcher, mrc]
    assert 'added' in watcher.ask('<varpush struct=odoPose i=2 cmd="var odoPose.pose"/>')
    mrc.send(MRC_HELLO + ''.join(pt(tick) for tick in range(1, 5)).encode())
    pushed = watcher.until(lambda line: line == pose_reply(4))   # updates of one turn run once
    assert set(pushed) <= {pose_reply(2), pose_reply(4)}, pushed
    assert mrc.ask('var odoPose.pose') == pose_reply(4)          # the first line mrc is sent
    mrc.send('<pt tod="0.000000" x="0.0000" y="0.0000 " th="0.0000 " />\n')   # "no pose yet"
    assert mrc.ask('var odoPose.pose') == pose_reply(4)
    mrc.send('q\n')
    assert mrc.to_eof() == ['</xmlServer>']


def test_a_pose_that_cannot_be_read_is_told_once_per_client(start: Start,
                                                            clients: list[Raw]) -> None:
    server = start()
    first, second = Raw(server.port), Raw(server.port)
    clients += [first, second]
    for raw in (first, second):
        raw.send(MRC_HELLO + b'<pt x="1" y="2" th="3" />\n' * 3
                 + b'<pt tod="1" x="a" y="2" th="3"/>\n')
        assert raw.line() == ('<pt warning="a pose needs tod= (tod= x= y= th=): pose not taken '
                              '(said once)"/>')
        assert raw.ask('var odoPose.pose').startswith('<var name="odoPose.pose"')
    assert first.ask('var odoPose.pose') == second.ask('var odoPose.pose')


def test_pt_has_its_help(start: Start, clients: list[Raw]) -> None:
    raw = Raw(start().port)
    clients.append(raw)
    raw.send('<pt help/>\n')
    lines = raw.until_done()
    assert lines[0] == '<help subject="PT">' and lines[-2:] == ['</help>', '<pt info="done"/>']
    assert any('odoPose.pose; no reply' in line for line in lines), lines


def _rss(pid: int) -> int:
    """Resident memory of process ``pid`` (bytes)."""
    found = re.search(r'VmRSS:\s+(\d+) kB', pathlib.Path(f'/proc/{pid}/status').read_text())
    assert found is not None, f'no VmRSS for process {pid}'
    return int(found.group(1)) * 1024


def _flood(raw: Raw, ticks: range) -> None:
    """mrc's lines for ``ticks``, sent as fast as the server takes them (each 10 000 within
    :data:`DEADLINE`)."""
    raw.sock.settimeout(DEADLINE)
    for start in range(ticks.start, ticks.stop, 10_000):
        raw.send(''.join(pt(tick) for tick in range(start, min(start + 10_000, ticks.stop))))


def test_an_hour_of_mrc_gets_no_reply_and_memory_stays_flat(ros_domain: int) -> None:
    """360 000 ``pt`` lines — an hour at 100 Hz — as fast as the real ``xml_server`` reads them,
    then a command: its reply is the only line sent, and it holds the last pose; the server's
    resident memory grows by less than :data:`FLAT` from six minutes in to the hour's end."""
    with ChildProcess([find_executable('wurde_mcp', 'xml_server'), '-p', '0']) as server:
        listening = re.search(r'127\.0\.0\.1:(\d+)',
                              server.expect('xml_server listening on', timeout=DEADLINE))
        assert listening is not None
        port = int(listening.group(1))
        mrc = Raw(port)
        try:
            assert mrc.greeting == ['<?xml version="1.0" encoding="UTF-8"?>',
                                    '<xmlServer name="xmlServer" version="1.0">']
            began = time.monotonic()
            mrc.send(MRC_HELLO)
            _flood(mrc, range(WARM_UP))
            assert mrc.ask('var odoPose.pose') == pose_reply(WARM_UP - 1)
            before = _rss(server.process.pid)
            _flood(mrc, range(WARM_UP, HOUR))
            mrc.send('var odoPose.pose\nq\n')
            assert mrc.to_eof(timeout=DEADLINE) == [pose_reply(HOUR - 1), '</xmlServer>']
            grown = _rss(server.process.pid) - before
            took = time.monotonic() - began
        finally:
            mrc.close()
        assert grown < FLAT, f'xml_server grew by {grown} bytes over {HOUR - WARM_UP} pt lines'
        assert server.process.poll() is None, server.stderr
        assert server.stop() == 0, server.stderr
    print(f'{HOUR} pt lines in {took:.1f} s; resident memory grew {grown} bytes')
