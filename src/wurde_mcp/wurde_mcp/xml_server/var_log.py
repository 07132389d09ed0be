"""The var logfile: ``var log[=false]`` opens (closes) it, ``var log[=false] STRUCT`` starts (stops)
logging a structure or variable, ``var isLogging STRUCT`` asks (AU Robot Servers, "Online help",
VAR options).

AURS writes a logged structure's variables when they are updated.  :class:`VarLog` does so once
per server turn (:meth:`VarLog.poll`) for each logged name updated since: one line per variable,
``tod name value``, to ``<data path>/<server name>.var.log``.  The file is opened when a structure is
first logged; it stops growing at :data:`MAX_BYTES` (a warning in the server's log), so that a
client cannot fill the disk.
"""

from __future__ import annotations

import logging
import pathlib
import time
from typing import TextIO

from .variables import VarError, VariablePool, format_value

__all__ = ['MAX_BYTES', 'VarLog']

#: The largest a var logfile grows (bytes).
MAX_BYTES = 64 << 20

_log = logging.getLogger(__name__)


class VarLog:
    """The logfile of one pool and which of its structures and variables are logged."""

    def __init__(self, pool: VariablePool, path: pathlib.Path) -> None:
        self._pool = pool
        #: The logfile's path.
        self.path = path
        self._file: TextIO | None = None
        self._logged: dict[str, int] = {}        # name (lower case) -> updates written
        self._bytes = 0

    @property
    def is_open(self) -> bool:
        return self._file is not None

    def open(self) -> None:
        """Open (append to) the logfile. :raises VarError: it cannot be opened."""
        if self._file is not None:
            return
        try:
            self._file = self.path.open('a', encoding='utf-8')
        except OSError as exc:
            raise VarError(f'cannot open logfile {self.path}: {exc.strerror or exc}') from None
        self._bytes = self.path.stat().st_size

    def close(self) -> None:
        """Close the logfile (idempotent); logged structures stay marked."""
        if self._file is not None:
            self._file.close()
            self._file = None

    def start(self, name: str, on: bool) -> None:
        """Start (``on``) or stop logging ``name`` (a structure or variable, any case); starting
        opens the logfile. :raises VarError: the file cannot be opened."""
        key = name.lower().strip('.')
        if not on:
            self._logged.pop(key, None)
            return
        self.open()
        self._logged[key] = -1                  # written at the next poll

    def is_logged(self, name: str) -> bool:
        """Whether ``name`` or a structure it is in is logged."""
        parts = name.lower().strip('.').split('.')
        return any('.'.join(parts[:depth]) in self._logged for depth in range(1, len(parts) + 1))

    def poll(self) -> None:
        """Write the variables of each logged name updated since the last poll."""
        if self._file is None or not self._logged:
            return
        stamp = time.time()
        for key, seen in list(self._logged.items()):
            updates = self._pool.updates(key)
            if updates == seen:
                continue
            self._logged[key] = updates
            var = self._pool.find(key)
            for each in [var] if var is not None else self._pool.variables(key):
                self._write(f'{stamp:.6f} {each.name} {self._value(each)}\n')
        if self._file is not None:
            self._file.flush()

    def _write(self, line: str) -> None:
        assert self._file is not None
        if self._bytes + len(line) > MAX_BYTES:
            _log.warning('var logfile %s reached %d bytes: closed', self.path, MAX_BYTES)
            self.close()
            self._logged.clear()
            return
        self._file.write(line)
        self._bytes += len(line)

    @staticmethod
    def _value(var: object) -> str:
        try:
            return format_value(var.typ, var.current())[0]       # type: ignore[attr-defined]
        except VarError as exc:
            return f'? ({exc})'
