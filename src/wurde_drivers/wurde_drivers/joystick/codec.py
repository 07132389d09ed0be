"""The Linux joystick protocol: 8-byte ``struct js_event`` records (linux/joystick.h, API 1.0).

Each record is ``__u32 time`` (ms, the event's timestamp), ``__s16 value``, ``__u8 type``,
``__u8 number``, little-endian on the machines the kernel writes them for here (x86, ARM)::

    JS_EVENT_BUTTON 0x01   value 0 or 1
    JS_EVENT_AXIS   0x02   value -32767 .. 32767
    JS_EVENT_INIT   0x80   ORed into the type of the synthetic events sent on open: one per
                           axis and button with its current state

Pure functions over bytes (no rclpy, no wurde_core): :func:`encode_event` and
:class:`JsDecoder`, which keeps a partial record for the next read and drops (and counts) a record
whose type is neither a button nor an axis.
"""

from __future__ import annotations

import dataclasses
import struct

from ..errors import CodecError

__all__ = ['AXIS_MAX', 'EVENT_SIZE', 'JS_EVENT_AXIS', 'JS_EVENT_BUTTON', 'JS_EVENT_INIT',
           'JsDecoder', 'JsEvent', 'decode_event', 'encode_event']

JS_EVENT_BUTTON = 0x01
JS_EVENT_AXIS = 0x02
JS_EVENT_INIT = 0x80
#: Largest axis deflection the joystick driver reports (and the negative of the smallest).
AXIS_MAX = 32767
_RECORD = struct.Struct('<IhBB')
EVENT_SIZE = _RECORD.size   # 8


@dataclasses.dataclass(frozen=True)
class JsEvent:
    """One js_event: ``kind`` is :data:`JS_EVENT_BUTTON` or :data:`JS_EVENT_AXIS` (the init flag
    apart, in ``init``); ``time_ms`` wraps at 2**32."""

    kind: int
    number: int
    value: int
    time_ms: int = 0
    init: bool = False

    @property
    def is_axis(self) -> bool:
        return self.kind == JS_EVENT_AXIS

    @property
    def is_button(self) -> bool:
        return self.kind == JS_EVENT_BUTTON


def encode_event(event: JsEvent) -> bytes:
    """The 8 bytes the kernel would write for ``event``.

    :param event: a button or axis event.
    :raises CodecError: a kind that is neither button nor axis, or a field out of its C type's range.
    """
    if event.kind not in (JS_EVENT_BUTTON, JS_EVENT_AXIS):
        raise CodecError(f'js_event type {event.kind:#x} is neither button nor axis')
    try:
        return _RECORD.pack(event.time_ms & 0xFFFFFFFF, event.value,
                            event.kind | (JS_EVENT_INIT if event.init else 0), event.number)
    except struct.error as error:
        raise CodecError(f'js_event out of range: {event}') from error


def decode_event(record: bytes) -> JsEvent:
    """One 8-byte record.

    :param record: exactly 8 bytes, as read from ``/dev/input/jsN``.
    :raises CodecError: not 8 bytes, or a type that is neither button nor axis.
    """
    if len(record) != EVENT_SIZE:
        raise CodecError(f'a js_event is {EVENT_SIZE} bytes, not {len(record)}')
    time_ms, value, kind, number = _RECORD.unpack(record)
    base = kind & ~JS_EVENT_INIT
    if base not in (JS_EVENT_BUTTON, JS_EVENT_AXIS):
        raise CodecError(f'js_event type {kind:#04x} is neither button nor axis')
    return JsEvent(kind=base, number=number, value=value, time_ms=time_ms,
                   init=bool(kind & JS_EVENT_INIT))


class JsDecoder:
    """Bytes as they are read (any split) -> events.  A partial record waits for the next
    :meth:`feed`; a record of an unknown type is dropped and counted in :attr:`dropped`."""

    def __init__(self) -> None:
        self._pending = b''
        self.dropped = 0
        self.decoded = 0

    @property
    def pending(self) -> int:
        """Bytes of a partial record kept for the next read."""
        return len(self._pending)

    def reset(self) -> None:
        """Forget a partial record (the device was reopened: it starts on a record boundary)."""
        self._pending = b''

    def feed(self, data: bytes) -> list[JsEvent]:
        """The events in ``data``; a partial record is kept for the next call.

        :param data: bytes as read from the device, in any pieces; records of an unknown type are
            dropped and counted.
        """
        buffer = self._pending + bytes(data)
        whole = len(buffer) - len(buffer) % EVENT_SIZE
        self._pending = buffer[whole:]
        events: list[JsEvent] = []
        for start in range(0, whole, EVENT_SIZE):
            try:
                events.append(decode_event(buffer[start:start + EVENT_SIZE]))
            except CodecError:
                self.dropped += 1
        self.decoded += len(events)
        return events
