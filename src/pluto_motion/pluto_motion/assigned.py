"""A consumer named by its stream, or by an alias the MCP assigns (WURDE 6.3: STRAT_ASSIGNED): the
guide's modules take their streams from the MCP's mappings, and an option may name one directly
when the module runs on its own (``ros2 run``)."""

from __future__ import annotations

from typing import Any

from wurde_core import ConnectionStrategy

__all__ = ['consumer']


def consumer(cls: type, stream: str | None, alias: str) -> Any:
    """``cls(stream)`` when a stream is given, else ``cls(ConnectionStrategy.ASSIGNED, alias)``."""
    return cls(stream) if stream else cls(ConnectionStrategy.ASSIGNED, alias)
