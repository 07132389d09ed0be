"""What an xmlServer allows and counts: :class:`ServerSettings` (port, limits per client) and
:class:`ServerStats`.

AU Robot Servers, "Interface description": "each server has 1 port and allows up to 10
simultaneous clients (port numbers used are from 24919 to 24930)".
"""

from __future__ import annotations

import dataclasses
import math

from .command import NAME

__all__ = ['PORTS', 'ServerSettings', 'ServerStats']

#: The Mobotware servers' ports (the seed: "port numbers used are from 24919 to 24930").
PORTS = range(24919, 24931)


@dataclasses.dataclass(frozen=True, kw_only=True)
class ServerSettings:
    """How an :class:`XmlServer` listens and what it allows each client.

    :raises ValueError: a setting out of range (the port not one of :data:`PORTS` nor 0).
    """

    #: The greeting's root tag and the server's name in ``help``.
    name: str = 'xmlServer'
    #: The server's version, in the greeting and ``help``.
    version: str = '1.0'
    #: Address to bind: 127.0.0.1 this host only, 0.0.0.0 every interface.
    host: str = '127.0.0.1'
    #: 24919..24930 as the Mobotware servers, or 0: any free port (tests, many servers on one host).
    port: int = 24919
    #: Simultaneous clients; one more is told so and closed.
    max_clients: int = 10
    #: Longest command line (bytes, without its newline); a longer one is dropped with a warning.
    max_line: int = 65536
    #: Output held for one client (bytes); a client that lets more pile up is disconnected.
    send_buffer: int = 1 << 20
    #: A client that sent nothing and was sent nothing for this long is closed (s).
    idle_timeout: float = 300.0
    #: Pushes per client.
    max_pushes: int = 32
    #: Shortest period of a time push (s).
    min_push_period: float = 0.01
    #: Lines handled per client per turn, so that a flooding client cannot starve the others.
    lines_per_turn: int = 50
    #: Directory of the var logfile ``<name>.var.log`` (AURS's dataPath; ``var log``).
    data_path: str = '.'

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not NAME.fullmatch(self.name):
            raise ValueError(f'name {self.name!r} is not a tag name')
        if not isinstance(self.version, str):
            raise ValueError(f'version {self.version!r} is not a string')
        if isinstance(self.port, bool) or not isinstance(self.port, int) or \
                (self.port != 0 and self.port not in PORTS):
            raise ValueError(f'port {self.port!r} is not one of {PORTS.start}..{PORTS.stop - 1} '
                             'nor 0 (any free port)')
        for key, least in (('max_clients', 1), ('max_line', 16), ('send_buffer', 1024),
                           ('lines_per_turn', 1)):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int) or value < least:
                raise ValueError(f'{key} {value!r} is not an integer of at least {least}')
        if not isinstance(self.data_path, str) or not self.data_path:
            raise ValueError(f'data_path {self.data_path!r} is not a directory name')
        if isinstance(self.max_pushes, bool) or not isinstance(self.max_pushes, int) \
                or self.max_pushes < 0:
            raise ValueError(f'max_pushes {self.max_pushes!r} is not a count')
        for key in ('idle_timeout', 'min_push_period'):
            value = getattr(self, key)
            if not isinstance(value, (int, float)) or not 0 < value < math.inf:
                raise ValueError(f'{key} {value!r} is not a positive number of seconds')


@dataclasses.dataclass
class ServerStats:
    """What an :class:`XmlServer` counted since it started."""

    accepted: int = 0               #: sessions begun
    refused: int = 0                #: connections refused: max_clients were connected
    lines: int = 0                  #: command lines handled (blank lines not counted)
    dropped_long_lines: int = 0     #: lines longer than max_line, dropped
    malformed: int = 0              #: lines that were not a command
    slow_disconnects: int = 0       #: clients disconnected for letting send_buffer fill
    idle_disconnects: int = 0       #: clients closed after idle_timeout
    peak_output: int = 0            #: the most output ever held for one client (bytes)
    peak_input: int = 0             #: the most input ever held for one client (bytes)
