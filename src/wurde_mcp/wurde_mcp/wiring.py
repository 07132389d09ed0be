"""Whether the mappings agree with what the suppliers and consumers really are (guide 6.2).

A mapping connects a consumer of interface ``I`` to stream ``S``.  If the module that supplies
``S`` supplies it as another interface ``J``, the consumer subscribes to ``S`` with ``I``'s message
types, DDS never matches the two, and the consumer silently never gets data.  So every such
disagreement is refused, naming the mapping's file and line and both types:

- at configure time from the files alone (two mappings that use one stream as two interfaces)
  and from the registration pass (each internal binary's ``-r`` report of what it supplies and
  what its consumers are);
- at run time, when a module's capability report or heartbeat shows a supplier that the files
  could not know: the MCP logs the error and refuses to assign that stream.

A supplier that serves ``S`` as ``J`` and also as ``I`` on the typed view ``S/I``
(:func:`wurde_core.naming.typed_view`, as every base does with its two drive interfaces) agrees
with the mapping: the consumer is given ``S/I``.
"""

from __future__ import annotations

from collections.abc import Iterable

from wurde_core.naming import typed_view

from .config import Mapping


def served_stream(mapping: Mapping, supplies: Iterable[tuple[str, str]]) -> str:
    """The stream that serves ``mapping`` among a supplier's ``(interface, stream)`` list: the
    typed view of the mapped stream when the supplier offers one for the mapping's interface,
    else the mapped stream itself."""
    view = typed_view(mapping.source, mapping.interface)
    return view if (mapping.interface, view) in set(supplies) else mapping.source


def supplier_conflict(mapping: Mapping, supplier: str,
                      supplies: Iterable[tuple[str, str]]) -> str | None:
    """Why ``mapping`` disagrees with module ``supplier``'s ``(interface, stream)`` list, or
    ``None`` when it does not supply the mapping's stream as another interface (or supplies the
    mapping's interface on the stream's typed view too)."""
    supplies = list(supplies)
    if served_stream(mapping, supplies) != mapping.source:
        return None
    for interface, stream in supplies:
        if stream == mapping.source and interface != mapping.interface:
            return (f'mapping connects {mapping.interface} object "{mapping.object or "*"}" of '
                    f'module "{mapping.module}" to stream "{mapping.source}", but module '
                    f'"{supplier}" supplies that stream as {interface}')
    return None


def consumer_conflict(mapping: Mapping, consumes: Iterable[tuple[str, str]]) -> str | None:
    """Why ``mapping`` disagrees with its module's ``(interface, object)`` consumers, or ``None``
    (a mapping without an object, or for an object the module does not declare, agrees)."""
    if not mapping.object:
        return None
    for interface, obj in consumes:
        if obj == mapping.object and interface != mapping.interface:
            return (f'mapping gives {mapping.interface} object "{mapping.object}" of module '
                    f'"{mapping.module}" stream "{mapping.source}", but that module declares '
                    f'"{mapping.object}" as {interface}')
    return None
