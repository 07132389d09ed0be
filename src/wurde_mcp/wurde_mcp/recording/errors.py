"""Exceptions of the recording tools, rooted in the suite's :class:`WurdeError`."""

from __future__ import annotations

from wurde_idl.errors import WurdeError

__all__ = ['BagError', 'MessageTypeError', 'RecordingError']


class RecordingError(WurdeError):
    """Something ``record`` or ``replay`` cannot do; the message says what and where."""


class BagError(RecordingError):
    """A bag (directory, ``metadata.yaml`` or storage file) that cannot be read or written as
    asked; the message names the file and the reason."""


class MessageTypeError(RecordingError, LookupError):
    """A message type that is not installed here, or a name that is not a type's."""
