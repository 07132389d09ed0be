"""Exceptions of wurde_core, all rooted in the suite's :class:`WurdeError`."""

from __future__ import annotations

from wurde_idl.errors import ConfigError, UnknownInterfaceError, WurdeError

__all__ = ['ConfigError', 'DirectionError', 'LockedError', 'NotRegisteredError', 'OptionError',
           'RegistrationError', 'UnknownInterfaceError', 'WurdeError']


class RegistrationError(WurdeError):
    """An object was registered twice, or registered after the manager was cleaned up."""


class NotRegisteredError(WurdeError):
    """An object was used for communication before it was registered with a CommsManager."""


class DirectionError(WurdeError):
    """A channel was used against its direction (a consumer publishing info or data, ...)."""


class LockedError(WurdeError):
    """A write to a Writable value was refused by the lock its supplier holds."""


class OptionError(WurdeError):
    """A command-line option is wrong (parse_options prints usage and exits with status 2)."""
