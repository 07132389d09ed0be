"""WURDE's enumerations as Python enums, with the values of the messages' table
(``wurde_idl.types.BUILTIN_ENUMS``; a test holds them equal).

Seed: WURDE Programming Guide 3.3 (RunState, ProcessLocale, ProcessType, StatusMode,
ConnectionStrategy) and 3.2.4 (Writable locks).  ``RunState.RUN`` is the guide's ``STATE_RUN``,
``ConnectionStrategy.ASSIGNED`` its ``STRAT_ASSIGNED``.
"""

from __future__ import annotations

import enum



class RunState(enum.IntEnum):
    """A module's run state (guide 3.3, 5.2.1)."""

    RUN = 0
    IDLE = 1
    RESET = 2
    RESTART = 3
    QUIT = 4


class ProcessLocale(enum.IntEnum):
    """Whether the MCP started the module (internal) or it came by itself (external)."""

    INTERNAL = 0
    EXTERNAL = 1


class ProcessType(enum.IntEnum):
    """How the MCP watches a module: managed, unmanaged, or critical (the system stops without it)."""

    MANAGED = 0
    UNMANAGED = 1
    CRITICAL = 2


class StatusMode(enum.IntEnum):
    """A module's status in the MCP's table."""

    UNKNOWN = 0
    STARTING = 1
    ACTIVE = 2
    ZOMBIE = 3
    DEAD = 4
    FAILED = 5


class ConnectionStrategy(enum.IntEnum):
    """How a consumer finds its supplier: by stream name, assigned by the MCP, or any (3.3)."""

    NORMAL = 0
    ASSIGNED = 1
    AUTO = 2


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
