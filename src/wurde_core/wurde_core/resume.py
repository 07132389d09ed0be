"""State a module keeps across its restarts by the MCP: where a simulated robot stands, where the
localization thinks it is.

The MCP gives every module it starts a file for such state (:data:`STATE_ENV`, in its module log
directory) and tells it how many processes it started for the module before
(:func:`wurde_core.heartbeat.restart_count`).  A module keeps its state there with
:meth:`ResumeState.save` (JSON, replaced atomically, at most every ``every_s``) and, when it is a
restart, picks it up with :meth:`ResumeState.load`.  A first start ignores the file (a new run
starts where its config says), and a module started by hand has no file at all, so nothing is
written beside the user's files.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import time
from typing import Any

from . import module_context
from .heartbeat import restart_count

__all__ = ['STATE_ENV', 'ResumeState', 'replace_file', 'state_path']

#: Environment variable the MCP sets for the modules it starts: the path of the module's state file.
STATE_ENV = 'WURDE_MCP_STATE'


def replace_file(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` whole or not at all: a temporary file of this process beside it
    (``<path>.<pid>.tmp``, so two writers never share one), then ``os.replace``; a reader, or a
    process killed while writing, never sees half a file.

    :param path: the file.
    :param text: its new content (UTF-8).
    :raises OSError: when it cannot be written.
    """
    path = pathlib.Path(path)
    temporary = path.with_name(f'{path.name}.{os.getpid()}.tmp')
    temporary.write_text(text, encoding='utf-8')
    os.replace(temporary, path)


def state_path() -> pathlib.Path | None:
    """The state file the MCP gave this process (:data:`STATE_ENV`); None when started by hand."""
    path = module_context.getenv(STATE_ENV)
    return pathlib.Path(path) if path else None


class ResumeState:
    """The state file of this module, if the MCP gave it one."""

    def __init__(self, every_s: float = 0.5) -> None:
        """The file of :func:`state_path` (none when started by hand).

        :param every_s: the shortest time between two saves, in seconds (``force`` saves
            anyway).
        """
        self.path = state_path()
        self.every_s = every_s
        self._saved_at = -math.inf
        #: Why the last save failed (reported once by the caller through :attr:`failure`).
        self.failure: str | None = None

    @property
    def enabled(self) -> bool:
        return self.path is not None

    def load(self) -> tuple[dict[str, Any] | None, str]:
        """``(state, why)``: the saved state when this process is a restart and the file holds
        a JSON object, else None; ``why`` says which (for the module's log)."""
        if self.path is None:
            return None, 'not started by an MCP'
        if restart_count() == 0:
            return None, 'a first start'
        try:
            state = json.loads(self.path.read_text(encoding='utf-8'))
        except FileNotFoundError:
            return None, f'{self.path}: no state saved by the last process'
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
            return None, f'{self.path}: unreadable ({error})'
        if not isinstance(state, dict):
            return None, f'{self.path}: not a JSON object'
        return state, f'restart {restart_count()}, state of {self.path}'

    def save(self, state: dict[str, Any], *, force: bool = False) -> bool:
        """Write ``state`` if it is time to.  A failure is kept in :attr:`failure`, never
        raised: the module goes on.

        :param state: a JSON-able dict.
        :param force: write it even if ``every_s`` has not passed since the last save.
        :returns: whether it was written (False without a state file).
        """
        if self.path is None:
            return False
        now = time.monotonic()
        if not force and now - self._saved_at < self.every_s:
            return False
        self._saved_at = now
        try:
            replace_file(self.path, json.dumps(state))
        except OSError as error:
            self.failure = f'{self.path}: cannot save ({error.strerror or error})'
            return False
        self.failure = None
        return True
