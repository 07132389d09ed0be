"""What the server's command modules use of it (:class:`ServerHost`, which
:class:`~.server.XmlServer` is): the standard commands, ``module``, ``alive`` and the interfaces
to other servers are typed against this, so imports point one way (the server imports them)."""

from __future__ import annotations

import socket
from collections.abc import Callable
from typing import Protocol

from .command import Command
from .command_table import Handler
from .session import Session
from .settings import ServerSettings
from .user_vars import UserVariables
from .variables import VariablePool

__all__ = ['ServerHost', 'Watcher']


class Watcher(Protocol):
    """A socket of the server's own (an interface to another server) the selector watches."""

    def on_event(self, mask: int) -> None: ...


class ServerHost(Protocol):
    """The server as its command modules see it."""

    pool: VariablePool
    settings: ServerSettings
    user_vars: UserVariables
    turn_gap: float

    @property
    def port(self) -> int: ...

    def add_command(self, name: str, handler: Handler, help_line: str, *,
                    help_text: str | None = None, group: str | None = None) -> None: ...

    def remove_command(self, name: str) -> None: ...

    def command_groups(self) -> dict[str, list[str]]: ...

    def help_handler(self, client: Session, command: Command) -> list[str]: ...

    def add_poller(self, poller: Callable[[float], None]) -> None: ...

    def remove_poller(self, poller: Callable[[float], None]) -> None: ...

    def watch(self, sock: socket.socket, watcher: Watcher, events: int) -> None: ...

    def unwatch(self, sock: socket.socket) -> None: ...
