"""Stream assignment: the MCP's answers on McpRequest stream ``mcp`` (seed: WURDE guide 6.2, 6.3).

ASSIGNED gives a module's object the stream its mapping names; AUTO takes a mapping for the
interface, else any module that supplies it; NORMAL (kind start) starts the module that supplies
a stream.  A supplier that is known to supply the mapped stream as another interface is never
assigned (see :mod:`wurde_mcp.wiring`): the answer and the MCP's log name the mapping's file,
line and both types.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any, Protocol

from wurde_core import ConnectionStrategy, StatusMode, g_error

from .config import Mapping, McpConfig, where
from .wiring import consumer_conflict, served_stream, supplier_conflict

KIND_ASSIGN, KIND_START, KIND_CAPABILITIES = 0, 1, 2


class WatchedModule(Protocol):
    """What assignment needs to know of a module (the supervisor's ``Module``)."""

    supplies: list[tuple[str, str]]
    consumes: list[tuple[str, str]]
    wanted: bool
    status: StatusMode

    @property
    def name(self) -> str: ...

    @property
    def internal(self) -> bool: ...


class StreamDesk:
    """Answers assignment, start and capability requests from the modules."""

    def __init__(self, mcp: Any, config: McpConfig, modules: dict[str, Any],
                 start: Callable[[str], bool]) -> None:
        self.mcp = mcp
        self.config = config
        self.modules = modules
        self.start = start
        self._reported: set[tuple[str, str, int, str]] = set()

    def supplier_of(self, stream: str) -> Any | None:
        return next((m for m in self.modules.values()
                     if any(s == stream for _, s in m.supplies)), None)

    def check(self, module: WatchedModule) -> list[tuple[Mapping, str]]:
        """Log (once each) every mapping that ``module``'s suppliers or consumers contradict;
        return those mappings with the reasons."""
        found = []
        for mapping in self.config.mappings:
            reason = supplier_conflict(mapping, module.name, module.supplies)
            if reason is None and mapping.module == module.name:
                reason = consumer_conflict(mapping, module.consumes)
            if reason is None:
                continue
            found.append((mapping, reason))
            key = (module.name, mapping.path, mapping.line, reason)
            if key not in self._reported:
                self._reported.add(key)
                g_error(f'MCP: {where(mapping)}: {reason}; that mapping is not used')
        return found

    def serve(self) -> None:
        """Answer every request that arrived."""
        while self.mcp.get_next_request():
            request = self.mcp.requests
            kind = request.kind.get_value()
            module = request.module.get_value()
            if kind == KIND_CAPABILITIES:
                target = self.modules.get(module)
                if target is not None:
                    target.supplies = list(zip(request.provided_interfaces.get_value(),
                                               request.provided_streams.get_value()))
                    target.consumes = list(zip(request.consumed_interfaces.get_value(),
                                               request.consumed_objects.get_value()))
                    self.check(target)
                continue
            if kind == KIND_ASSIGN:
                self._answer(request, *self.assign(
                    module, request.interface.get_value(), request.object.get_value(),
                    ConnectionStrategy(request.strategy.get_value())))
            elif kind == KIND_START:
                wanted = request.object.get_value()
                supplier = self.supplier_of(wanted)
                ok = supplier is not None and self.start(supplier.name)
                self._answer(request, ok, wanted,
                             '' if ok else f'no startable module supplies {wanted}')

    def _candidates(self, module: str, interface: str, obj: str,
                    strategy: ConnectionStrategy) -> Iterable[Mapping]:
        for mapping in self.config.mappings_for(module):
            if strategy == ConnectionStrategy.ASSIGNED and mapping.object == obj:
                yield mapping
            elif strategy == ConnectionStrategy.AUTO and mapping.interface == interface \
                    and mapping.object in ('', obj):
                yield mapping

    def assign(self, module: str, interface: str, obj: str,
               strategy: ConnectionStrategy) -> tuple[bool, str, str]:
        """``(success, stream, detail)`` for one assignment request."""
        stream = ''
        for mapping in self._candidates(module, interface, obj, strategy):
            if mapping.interface != interface:
                return False, '', (f'{where(mapping)}: the mapping makes "{obj}" of module '
                                   f'"{module}" a {mapping.interface}, but the module asks for '
                                   f'it as {interface}')
            supplier = self.supplier_of(mapping.source)
            stream = mapping.source
            if supplier is not None:
                reason = supplier_conflict(mapping, supplier.name, supplier.supplies)
                if reason is not None:
                    return False, '', f'{where(mapping)}: {reason}'
                stream = served_stream(mapping, supplier.supplies)
            break
        if not stream and strategy == ConnectionStrategy.AUTO:
            stream = next((s for m in self.modules.values() for i, s in m.supplies
                           if i == interface), '')
        if not stream:
            return False, '', (f'no mapping for {interface} object "{obj}" of module "{module}"'
                               if strategy == ConnectionStrategy.ASSIGNED
                               else f'no supplier of {interface} known')
        supplier = self.supplier_of(stream)
        if supplier is not None and supplier.internal and not supplier.wanted \
                and supplier.status != StatusMode.FAILED:
            self.start(supplier.name)
        return True, stream, ''

    def _answer(self, request: Any, success: bool, stream: str, detail: str) -> None:
        info = self.mcp.info
        info.request_id.set_value(request.request_id.get_value())
        info.kind.set_value(request.kind.get_value())
        info.strategy.set_value(request.strategy.get_value())
        info.module.set_value(request.module.get_value())
        info.interface.set_value(request.interface.get_value())
        info.object.set_value(request.object.get_value())
        info.stream.set_value(stream)
        info.success.set_value(success)
        info.detail.set_value(detail)
        self.mcp.publish_info()
