"""Exceptions of wurde_drivers, all rooted in the suite's :class:`WurdeError`.

This module imports only ``wurde_idl.errors`` (pure Python), so codecs and the simulated world may
use it without pulling in rclpy or wurde_core.  :class:`MapError` is the suite's
(``wurde_idl.errors.MapError``), named here too so that driver code finds every error it may
raise in one place.
"""

from __future__ import annotations

from wurde_idl.errors import ConfigError, MapError, WurdeError

__all__ = ['CodecError', 'ConfigError', 'DeviceError', 'DeviceTimeout', 'DriverError', 'MapError',
           'WurdeError']


class DriverError(WurdeError):
    """Root of every error raised by a driver, an emulator or the simulated world."""


class CodecError(DriverError, ValueError):
    """Bytes that are not a valid telegram of the device's protocol (bad CRC, framing, length).

    Every codec raises this (or a subclass) and nothing else when given bad bytes; the fuzz tests
    hold each codec to that contract.
    """


class DeviceError(DriverError):
    """The device answered, but not as the protocol says it must (NAK, refused mode, ...)."""


class DeviceTimeout(DeviceError):
    """The device did not answer in time (silent line, vanished device)."""
