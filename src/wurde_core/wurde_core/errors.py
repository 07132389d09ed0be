"""Exceptions of wurde_core, all rooted in the suite's :class:`WurdeError`."""

from __future__ import annotations

from wurde_idl.errors import ConfigError, UnknownInterfaceError, WurdeError

__all__ = ['ConfigError', 'DirectionError', 'InvalidTypeError', 'InvalidValueError', 'LockedError',
           'MemberError', 'NotRegisteredError', 'OptionError', 'RegistrationError',
           'UnknownInterfaceError', 'WurdeError']


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


class MemberError(WurdeError, AttributeError):
    """A member that the interface does not have (``foo.data.rangs``), or an interface that no
    installed package defines, asked for as an attribute; ``hasattr`` answers False."""


class InvalidValueError(WurdeError, ValueError):
    """An argument with a value the call can not take (an empty module name, a PROCESS lock
    without its owner, an unknown log level)."""


class InvalidTypeError(WurdeError, TypeError):
    """An argument of the wrong type (registering something that is not a RobotObject)."""
