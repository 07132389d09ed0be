"""The exception tree shared by the whole suite.

Every error the suite raises on purpose derives from :class:`WurdeError`; errors about a file a user
wrote (interface XML, configuration) are :class:`ConfigError` and name the file, the line and the
reason, so that the message alone tells the user what to fix.
"""

from __future__ import annotations

import os


class WurdeError(Exception):
    """Root of every error raised by the WURDE suite."""


class ConfigError(WurdeError):
    """A file written by a user is wrong: names the file, the line (when known) and the reason."""

    def __init__(self, path: str | os.PathLike[str], line: int | None, reason: str) -> None:
        """The error ``path:line: reason`` (``path: reason`` without a line).

        :param path: the file that is wrong (or a label such as ``<environment>``).
        :param line: its line, 1-based; None (or 0) when unknown.
        :param reason: what is wrong, for the user to fix.
        """
        self.path = os.fspath(path)
        self.line = line
        self.reason = reason
        where = f'{self.path}:{line}' if line else self.path
        super().__init__(f'{where}: {reason}')


class InterfaceError(ConfigError):
    """An interface definition file is refused."""


class MapError(ConfigError):
    """A map file (:mod:`wurde_idl.mapfile`, an occupancy grid's YAML) is refused: file, line and
    reason like every configuration error."""


class UnknownInterfaceError(WurdeError, LookupError):
    """No installed package defines an interface of that name."""
