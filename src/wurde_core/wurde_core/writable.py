"""Writable: access-controlled info and request values (guide 3.2.4).

A supplier may lock a member, or its whole device, so that only suppliers, only consumers, or only
one named process may change it.  The supplier holds the locks and sends them with its info, so a
consumer's :meth:`Writable.set_value` refuses a locked write at once with :class:`LockedError`;
the supplier refuses it again on arrival (a consumer can not get round a lock by ignoring it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .enums import LockMode
from .errors import LockedError

if TYPE_CHECKING:
    from .fields import FieldSpec

#: Key of a device-wide lock in a lock table.
DEVICE = ''


def lock_refusal(locks: dict[str, tuple[LockMode, str]], field: str, writer_role: str,
                 writer: str) -> tuple[LockMode, str] | None:
    """The lock that forbids ``writer`` to change ``field``, or ``None`` when the write is
    allowed.  A field lock is checked before the device's.

    :param locks: the lock table, member name (:data:`DEVICE` for the device) -> (mode, owner).
    :param field: the member written.
    :param writer_role: ``'supplier'`` or ``'consumer'``, the writing process's role.
    :param writer: the writing process's module name (for PROCESS locks).
    :returns: ``(mode, owner)`` of the forbidding lock, or None.
    """
    for key in (field, DEVICE):
        mode, owner = locks.get(key, (LockMode.NONE, ''))
        if mode == LockMode.SUPPLIERS and writer_role != 'supplier':
            return mode, owner
        if mode == LockMode.CONSUMERS and writer_role != 'consumer':
            return mode, owner
        if mode == LockMode.PROCESS and writer != owner:
            return mode, owner
    return None


def describe_lock(mode: LockMode, owner: str) -> str:
    """Human wording of a lock, for error messages (``locked to consumers only``).

    :param mode: the lock's mode.
    :param owner: the owning process, named for a PROCESS lock.
    """
    if mode == LockMode.PROCESS:
        return f'locked to process "{owner}"'
    return f'locked to {mode.name.lower()} only'


class Writable:
    """One info or request member: ``get_value()``, ``set_value(v)`` and, on a supplier's info,
    ``lock(...)`` / ``lock_to_process(name)`` / ``unlock()``."""

    __slots__ = ('_struct', '_spec')

    def __init__(self, struct: Any, spec: 'FieldSpec') -> None:
        """Made by the ``info`` and ``requests`` structures, one per member on first use.

        :param struct: the InfoStruct holding this member (not imported: structs imports us).
        :param spec: how the member is read from and written to the message.
        """
        self._struct = struct
        self._spec = spec

    @property
    def name(self) -> str:
        """The member's name."""
        return self._spec.name

    def get_value(self) -> Any:
        """The member's current value."""
        return self._spec.get(self._struct.ros_message())

    def set_value(self, value: Any) -> None:
        """Change the value (sent by the next ``publish_info`` or ``publish_request``).

        :param value: the new value, coerced to the member's type (``8`` for a Double is 8.0; a
            geometry view or an enum for those types).
        :raises LockedError: when a lock held by the supplier forbids this process the write.
        :raises DirectionError: on a consumer's info or a supplier's requests.
        """
        owner = self._struct.__dict__['_owner']
        if owner is not None:
            owner._check_write(self._struct.__dict__['_channel'], self._spec.name)
        self._spec.set(self._struct.ros_message(), value)
        self._struct._written().add(self._spec.name)

    def lock(self, mode: LockMode, owner: str = '') -> None:
        """Lock this member (suppliers only): who may change it from now on.

        :param mode: SUPPLIERS, CONSUMERS, PROCESS (``owner`` only) or NONE (unlock).
        :param owner: the module name of the one process a PROCESS lock allows.
        :raises DirectionError: on a consumer.
        :raises LockedError: on a member of a structure no RobotObject holds.
        """
        self._lock_owner().set_lock(self._spec.name, mode, owner)

    def lock_to_process(self, process: str) -> None:
        """Lock this member so that only one process may change it (suppliers only).

        :param process: that process's module name (its CommsManager's name).
        """
        self.lock(LockMode.PROCESS, process)

    def unlock(self) -> None:
        """Remove this member's lock."""
        self.lock(LockMode.NONE)

    def locked(self) -> tuple[LockMode, str]:
        """This member's lock as ``(mode, owner)`` (``LockMode.NONE`` when unlocked)."""
        return self._lock_owner().locks().get(self._spec.name, (LockMode.NONE, ''))

    def _lock_owner(self) -> Any:
        owner = self._struct.__dict__['_owner']
        if owner is None:
            raise LockedError(f'{self._spec.name}: only a RobotObject\'s info members have locks')
        return owner

    def __repr__(self) -> str:
        return f'Writable({self._spec.name}={self.get_value()!r})'
