"""The js_event codec (linux/joystick.h): golden bytes, round trips, any split of the byte
stream, the init flag, and records of an unknown type dropped and counted."""

from __future__ import annotations

import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from wurde_drivers.errors import CodecError
from wurde_drivers.joystick.codec import (EVENT_SIZE, JS_EVENT_AXIS, JS_EVENT_BUTTON, JS_EVENT_INIT,
                                          JsDecoder, JsEvent, decode_event, encode_event)

events = st.builds(JsEvent, kind=st.sampled_from([JS_EVENT_BUTTON, JS_EVENT_AXIS]),
                   number=st.integers(0, 255), value=st.integers(-32768, 32767),
                   time_ms=st.integers(0, 2**32 - 1), init=st.booleans())


def test_golden_bytes_as_the_kernel_writes_them() -> None:
    # time 0x01020304 ms, value -2 (0xfffe), type axis|init, number 7: little-endian
    event = JsEvent(JS_EVENT_AXIS, 7, -2, 0x01020304, init=True)
    assert encode_event(event) == bytes([0x04, 0x03, 0x02, 0x01, 0xFE, 0xFF, 0x82, 0x07])
    assert decode_event(bytes([0x04, 0x03, 0x02, 0x01, 0xFE, 0xFF, 0x82, 0x07])) == event
    assert decode_event(struct.pack('<IhBB', 5, 1, JS_EVENT_BUTTON, 3)) == JsEvent(JS_EVENT_BUTTON, 3, 1, 5)


def test_bad_events_and_records_are_refused_with_codec_error() -> None:
    with pytest.raises(CodecError):
        encode_event(JsEvent(0x04, 0, 0))
    with pytest.raises(CodecError):
        encode_event(JsEvent(JS_EVENT_AXIS, 256, 0))
    with pytest.raises(CodecError):
        decode_event(b'\x00' * 7)
    with pytest.raises(CodecError):
        decode_event(struct.pack('<IhBB', 0, 0, JS_EVENT_INIT, 0))   # init flag on no type


@settings(max_examples=200, deadline=None)
@given(st.lists(events, max_size=20), st.lists(st.integers(0, 200), max_size=10))
def test_any_split_of_the_stream_decodes_to_the_same_events(sent: list[JsEvent],
                                                            cuts: list[int]) -> None:
    stream = b''.join(encode_event(event) for event in sent)
    decoder = JsDecoder()
    got: list[JsEvent] = []
    start = 0
    for cut in sorted(min(cut, len(stream)) for cut in cuts):
        got += decoder.feed(stream[start:cut])
        assert decoder.pending == cut % EVENT_SIZE      # a partial record waits for the rest
        start = cut
    got += decoder.feed(stream[start:])
    assert got == sent
    assert decoder.pending == 0 and decoder.dropped == 0


@settings(max_examples=200, deadline=None)
@given(st.lists(st.one_of(events, st.integers(0, 255)), max_size=20))
def test_records_of_unknown_type_are_dropped_and_counted(items: list[JsEvent | int]) -> None:
    """An int stands for a record whose type byte is that value (maybe a valid one)."""
    stream, expected, bad = b'', [], 0
    for item in items:
        if isinstance(item, JsEvent):
            stream += encode_event(item)
            expected.append(item)
        elif item & ~JS_EVENT_INIT in (JS_EVENT_BUTTON, JS_EVENT_AXIS):
            stream += struct.pack('<IhBB', 9, 1, item, 2)
            expected.append(JsEvent(item & ~JS_EVENT_INIT, 2, 1, 9, init=bool(item & JS_EVENT_INIT)))
        else:
            stream += struct.pack('<IhBB', 9, 1, item, 2)
            bad += 1
    decoder = JsDecoder()
    assert decoder.feed(stream) == expected
    assert decoder.dropped == bad


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=200))
def test_garbage_never_raises(data: bytes) -> None:
    decoder = JsDecoder()
    got = decoder.feed(data)
    assert len(got) + decoder.dropped == len(data) // EVENT_SIZE
    assert decoder.pending == len(data) % EVENT_SIZE
