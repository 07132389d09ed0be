"""WURDE's enumerations as Python enums, built from the same table as the messages.

Seed: WURDE Programming Guide 3.3 (RunState, ProcessLocale, ProcessType, StatusMode,
ConnectionStrategy) and 3.2.4 (Writable locks).  ``RunState.RUN`` is the guide's ``STATE_RUN``,
``ConnectionStrategy.ASSIGNED`` its ``STRAT_ASSIGNED``.
"""

from __future__ import annotations

import enum

from wurde_idl.types import BUILTIN_ENUMS


def _make(name: str) -> type[enum.IntEnum]:
    return enum.IntEnum(name, [(value, number) for number, value in enumerate(BUILTIN_ENUMS[name])],
                        module=__name__)


RunState = _make('RunState')
ProcessLocale = _make('ProcessLocale')
ProcessType = _make('ProcessType')
StatusMode = _make('StatusMode')
ConnectionStrategy = _make('ConnectionStrategy')

#: Enum classes by WURDE type name, for converting message fields.
ENUMS: dict[str, type[enum.IntEnum]] = {
    'RunState': RunState, 'ProcessLocale': ProcessLocale, 'ProcessType': ProcessType,
    'StatusMode': StatusMode, 'ConnectionStrategy': ConnectionStrategy,
}


class LockMode(enum.IntEnum):
    """Who may change a Writable value (the values of ``wurde_interfaces/Lock``)."""

    NONE = 0
    SUPPLIERS = 1
    CONSUMERS = 2
    PROCESS = 3
