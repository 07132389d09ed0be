"""rFLEX codec fuzzers that reach the frame bodies (issue 10, section 6).

- validly framed reports with random data: the frame decodes to exactly the packet, and
  :func:`decode_report` gives what docs/protocols.md 3 says those bytes mean, or refuses;
- valid (stuffed) frames with one byte corrupted anywhere: never decoded;
- a stream of valid frames, corrupted frames and junk, cut anywhere: exactly the valid frames
  come out, in order — nothing lost, nothing spurious.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from wurde_drivers.errors import CodecError
from wurde_drivers.rflex import codec as rflex

FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

#: The reports of docs/protocols.md 3 ("Base -> host reports"), by (port, opcode).
REPORTS = {'motor': (2, 33), 'status': (1, 1), 'dio': (5, 1), 'sonar': (4, 2), 'joystick': (3, 0)}


def be(data: bytes, start: int, size: int, signed: bool = False) -> int:
    return int.from_bytes(data[start:start + size], 'big', signed=signed)


def expected_report(kind: str, data: bytes) -> object | None:
    """The report ``data`` holds, read from docs/protocols.md 3's layouts; None: too short/malformed."""
    if kind == 'motor':       # rv timestamp (4 each) axis (1) position velocity accel torque (4)
        if len(data) < 25:
            return None
        return rflex.MotorReport(axis=data[8], position=be(data, 9, 4, True),
                                 velocity=be(data, 13, 4, True),
                                 acceleration=be(data, 17, 4, True),
                                 torque=be(data, 21, 4, True), timestamp=be(data, 4, 4),
                                 rv=be(data, 0, 4, True))
    if kind == 'status':      # timestamp(4) voltage(4) brake(1)
        if len(data) < 9:
            return None
        return rflex.SystemStatus(voltage_raw=be(data, 4, 4), brake=data[8] != 0,
                                  timestamp=be(data, 0, 4))
    if kind == 'dio':         # timestamp(4) address(1) data(2)
        if len(data) < 7:
            return None
        return rflex.DioReport(address=data[4], value=be(data, 5, 2), timestamp=be(data, 0, 4))
    if kind == 'sonar':       # retval(4) timestamp(4), then (id(1) range(2)) triplets
        if len(data) < 8 or (len(data) - 8) % 3:
            return None
        readings = tuple((data[i], be(data, i + 1, 2)) for i in range(8, len(data), 3))
        return rflex.SonarReport(readings, timestamp=be(data, 4, 4), retval=be(data, 0, 4))
    # joystick: x at data[4..7], y at data[8..11], buttons at data[12]
    if len(data) < 13:
        return None
    return rflex.JoystickState(x=be(data, 4, 4, True), y=be(data, 8, 4, True), buttons=data[12],
                               timestamp=be(data, 0, 4))


def sized_binary(low: int, high: int) -> st.SearchStrategy[bytes]:
    return st.integers(low, high).flatmap(lambda n: st.binary(min_size=n, max_size=n))


@FUZZ
@given(st.sampled_from(sorted(REPORTS)), st.integers(0, 255), sized_binary(0, 40))
def test_framed_random_reports_decode_to_what_they_mean(kind: str, packet_id: int,
                                                        data: bytes) -> None:
    port, opcode = REPORTS[kind]
    packet = rflex.Packet(port, packet_id, opcode, data)
    frame = rflex.encode(packet, stuff=True)
    assert rflex.decode(frame) == packet
    raw = rflex.encode(packet)                  # a sender that never stuffs, like Player's base
    body = raw[2:-2]
    if not any(body[i] == 0x1B and body[i + 1] <= 3 for i in range(len(body) - 1)):
        assert rflex.decode(raw) == packet      # (the ambiguous rest: test_rflex_codec)
    expected = expected_report(kind, data)
    if expected is None:
        with pytest.raises(CodecError):
            rflex.decode_report(packet)
    else:
        assert rflex.decode_report(packet) == expected


@st.composite
def valid_packets(draw: st.DrawFn) -> rflex.Packet:
    """A packet a real base or host sends: a report with random fields, or a host command."""
    kind = draw(st.sampled_from(['motor', 'status', 'dio', 'sonar', 'joystick', 'command']))
    i32, u32 = st.integers(-(1 << 31), (1 << 31) - 1), st.integers(0, (1 << 32) - 1)
    packet_id = draw(st.integers(0, 255))
    if kind == 'motor':
        return rflex.MotorReport(draw(st.integers(0, 1)), draw(i32), draw(i32), draw(i32),
                                 draw(i32), draw(u32), draw(i32)).to_packet(packet_id)
    if kind == 'status':
        return rflex.SystemStatus(draw(u32), draw(st.booleans()), draw(u32)).to_packet(packet_id)
    if kind == 'dio':
        return rflex.DioReport(draw(st.integers(0, 255)), draw(st.integers(0, 0xFFFF)),
                               draw(u32)).to_packet(packet_id)
    if kind == 'sonar':
        readings = draw(st.lists(st.tuples(st.integers(0, 255), st.integers(0, 0xFFFF)),
                                 max_size=24))
        return rflex.SonarReport(tuple(readings), draw(u32), draw(u32)).to_packet(packet_id)
    if kind == 'joystick':
        return rflex.JoystickState(draw(i32), draw(i32), draw(st.integers(0, 255)),
                                   draw(u32)).to_packet(packet_id)
    return draw(st.sampled_from([rflex.system_report_req(100000, 3), rflex.set_defaults(),
                                 rflex.brake_release(), rflex.sonar_run(True),
                                 rflex.sys_status_poll(),
                                 rflex.set_dir(0, 51500, 51500, 30000, 1)]))


@st.composite
def corrupted(draw: st.DrawFn, packet: rflex.Packet) -> bytes:
    """``packet``'s stuffed frame with one byte (anywhere, delimiters too) replaced."""
    frame = bytearray(rflex.encode(packet, stuff=True))
    index = draw(st.integers(0, len(frame) - 1))
    frame[index] = draw(st.integers(0, 255).filter(lambda value: value != frame[index]))
    return bytes(frame)


@FUZZ
@given(valid_packets().flatmap(corrupted))
def test_a_valid_frame_with_one_byte_corrupted_is_never_decoded(frame: bytes) -> None:
    with pytest.raises(CodecError):
        rflex.decode(frame)
    deframer = rflex.Deframer()
    assert deframer.feed(frame) == [] and deframer.packets == 0


def _frames_only_where_placed(stream: bytes, placed: set[int]) -> bool:
    """No frame decodes from an ``ESC STX`` in ``stream`` other than the real ones."""
    start = stream.find(b'\x1b\x02')
    while start >= 0:
        end = stream.find(b'\x1b\x03', start + 2)
        if start not in placed and end >= 0:
            try:
                rflex.decode(stream[start:end + 2])
            except CodecError:
                pass
            else:
                return False
        start = stream.find(b'\x1b\x02', start + 1)
    return True


pieces = st.lists(st.one_of(
    valid_packets().map(lambda p: ('frame', p)),
    valid_packets().flatmap(corrupted).map(lambda b: ('junk', b)),
    st.binary(max_size=30).map(lambda b: ('junk', b))), max_size=10)


@FUZZ
@given(pieces, st.lists(st.integers(1, 64), min_size=1, max_size=10))
def test_a_stream_gives_exactly_its_valid_frames(items: list[tuple[str, object]],
                                                 cuts: list[int]) -> None:
    stream, placed = b'', set()
    for kind, item in items:
        if kind == 'frame':
            placed.add(len(stream))
            stream += rflex.encode(item, stuff=True)  # type: ignore[arg-type]
        else:
            stream += item  # type: ignore[operator]
    assume(_frames_only_where_placed(stream, placed))
    # A frame of our own ends the line: an open false start in the junk must not hold it back.
    end = rflex.sys_status_poll()
    stream += rflex.encode(end)
    deframer = rflex.Deframer()
    got: list[rflex.Packet] = []
    position, index = 0, 0
    while position < len(stream):
        size = cuts[index % len(cuts)]
        got += deframer.feed(stream[position:position + size])
        position, index = position + size, index + 1
    assert got == [item for kind, item in items if kind == 'frame'] + [end]
    assert deframer.packets == len(got)
