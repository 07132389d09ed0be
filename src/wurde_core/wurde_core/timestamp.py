"""WURDE's Time: microsecond precision and simple comparisons (guide 3.2.4).

Stored as integer microseconds since the epoch, so comparisons are exact.  Compares with another
Time, with a number of seconds (``time_t`` or a float), with a ``datetime`` and with a ROS
``builtin_interfaces/Time``.
"""

from __future__ import annotations

import datetime as _dt
import functools
import time as _time
from typing import Any

_US = 1_000_000


@functools.total_ordering
class Timestamp:
    """A point in time with microsecond precision.

    ``Time()`` is the epoch (an unset timestamp), ``Time(seconds)`` a given time,
    ``Time.now()`` the current wall-clock time.
    """

    __slots__ = ('_us',)

    def __init__(self, seconds: float = 0.0, microseconds: int = 0) -> None:
        """The time ``seconds`` + ``microseconds`` after the epoch.

        :param seconds: seconds since the epoch (rounded to the microsecond).
        :param microseconds: microseconds added to ``seconds``.
        """
        self._us = round(seconds * _US) + int(microseconds)

    @classmethod
    def now(cls) -> 'Timestamp':
        """The current wall-clock time."""
        return cls(microseconds=_time.time_ns() // 1000)

    @classmethod
    def from_msg(cls, stamp: Any) -> 'Timestamp':
        """From a ``builtin_interfaces/Time`` (nanoseconds are truncated to microseconds).

        :param stamp: anything with ``sec`` and ``nanosec``.
        """
        return cls(microseconds=stamp.sec * _US + stamp.nanosec // 1000)

    def to_msg(self, stamp: Any) -> Any:
        """Write this time into a ``builtin_interfaces/Time`` and return it.

        :param stamp: the message written into (a header's ``stamp``).
        """
        stamp.sec, rest = divmod(self._us, _US)
        stamp.nanosec = rest * 1000
        return stamp

    def get_seconds(self) -> float:
        """Seconds since the epoch, as a float."""
        return self._us / _US

    def get_microseconds(self) -> int:
        """Microseconds since the epoch."""
        return self._us

    def set_seconds(self, seconds: float) -> None:
        """Set from seconds since the epoch.

        :param seconds: seconds since the epoch (rounded to the microsecond).
        """
        self._us = round(seconds * _US)

    def _other(self, other: object) -> int | None:
        if isinstance(other, Timestamp):
            return other._us
        if isinstance(other, (int, float)):
            return round(other * _US)
        if isinstance(other, _dt.datetime):
            return round(other.timestamp() * _US)
        if hasattr(other, 'sec') and hasattr(other, 'nanosec'):
            return other.sec * _US + other.nanosec // 1000
        return None

    def __eq__(self, other: object) -> bool:
        value = self._other(other)
        return NotImplemented if value is None else self._us == value

    def __lt__(self, other: object) -> bool:
        value = self._other(other)
        if value is None:
            return NotImplemented
        return self._us < value

    def __hash__(self) -> int:
        return hash(self._us)

    def __sub__(self, other: 'Timestamp') -> float:
        """Seconds between two times."""
        return (self._us - other._us) / _US

    def __repr__(self) -> str:
        return f'Timestamp({self._us // _US}.{self._us % _US:06d})'


# The guide's name (3.2.4), kept as an alias of the canonical one (docs/naming.md).
Time = Timestamp
