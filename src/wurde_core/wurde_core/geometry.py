"""Point, Point3D, Pose and Pose3D with the guide's constructors and accessors (guide 3.2.4).

Each is a view over a ``wurde_interfaces`` message: built alone it owns a fresh message; taken from
a data or info member it wraps that member, so ``obj.data.location.x(1.0)`` writes into the event.
Accessors follow the C++ overloads: ``p.x()`` reads, ``p.x(2.0)`` writes; ``value()`` is the weight.
"""

from __future__ import annotations

import importlib
from typing import Any, ClassVar

_UNSET = object()


class _MessageType:
    """The ``wurde_interfaces`` message a view wraps, imported on first use (so that importing
    wurde_core needs no built workspace)."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._type: type[Any] | None = None

    def __get__(self, _obj: Any, _owner: Any = None) -> type[Any]:
        if self._type is None:
            self._type = getattr(importlib.import_module('wurde_interfaces.msg'), self._name)
        return self._type


class _View:
    _msg_type: ClassVar[type[Any]]
    _fields: ClassVar[tuple[str, ...]]
    __slots__ = ('_m',)

    def __init__(self, *values: float) -> None:
        names = self._positional(len(values))
        self._m = self._msg_type()
        for name, value in zip(names, values):
            setattr(self._m, name, float(value))

    @classmethod
    def _positional(cls, count: int) -> tuple[str, ...]:
        if count > len(cls._fields):
            raise TypeError(f'{cls.__name__} takes at most {len(cls._fields)} values, got {count}')
        return cls._fields[:count]

    @classmethod
    def wrap(cls, message: Any) -> Any:
        """A view writing through to ``message``.

        :param message: a ``wurde_interfaces`` message of the view's type (not copied).
        """
        view = cls.__new__(cls)
        view._m = message
        return view

    def to_msg(self) -> Any:
        """The underlying message (shared, not copied)."""
        return self._m

    def _access(self, name: str, value: Any) -> Any:
        if value is _UNSET:
            return getattr(self._m, name)
        setattr(self._m, name, float(value))
        return None

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return self._m == other._m

    def __repr__(self) -> str:
        values = ', '.join(f'{name}={getattr(self._m, name):g}' for name in self._msg_type.get_fields_and_field_types())
        return f'{type(self).__name__}({values})'


class _XY(_View):
    __slots__ = ()

    def x(self, value: Any = _UNSET) -> Any:
        """Read the x coordinate, or set it when given a value.

        :param value: the new x, m; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('x', value)

    def y(self, value: Any = _UNSET) -> Any:
        """Read the y coordinate, or set it when given a value.

        :param value: the new y, m; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('y', value)

    def value(self, value: Any = _UNSET) -> Any:
        """Read the weight, or set it when given a value.

        :param value: the new weight; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('weight', value)


class _Z:
    __slots__ = ()

    def z(self, value: Any = _UNSET) -> Any:
        """Read the z coordinate, or set it when given a value.

        :param value: the new z, m; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('z', value)  # type: ignore[attr-defined]


class _Theta:
    __slots__ = ()

    def theta(self, value: Any = _UNSET) -> Any:
        """Read theta, or set it when given a value.

        :param value: the new theta, rad about z; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('theta', value)  # type: ignore[attr-defined]


class PlanarPoint(_XY):
    """``Point()``, ``Point(x, y)``, ``Point(x, y, w)``."""

    __slots__ = ()
    _msg_type = _MessageType('Point')
    _fields = ('x', 'y', 'weight')


class Point3D(_Z, _XY):
    """``Point3D()``, ``Point3D(x, y, z)``, ``Point3D(x, y, z, w)``."""

    __slots__ = ()
    _msg_type = _MessageType('Point3D')
    _fields = ('x', 'y', 'z', 'weight')

    @classmethod
    def _positional(cls, count: int) -> tuple[str, ...]:
        if count not in (0, 3, 4):
            raise TypeError('Point3D takes (), (x, y, z) or (x, y, z, w)')
        return cls._fields[:count]


class PlanarPose(_Theta, _XY):
    """``Pose()``, ``Pose(x, y)``, ``Pose(x, y, t)``, ``Pose(x, y, t, w)``."""

    __slots__ = ()
    _msg_type = _MessageType('Pose')
    _fields = ('x', 'y', 'theta', 'weight')


# The guide's names (3.2.4), kept as aliases of the canonical ones (docs/naming.md).
Point = PlanarPoint
Pose = PlanarPose


class Pose3D(_Theta, _Z, _XY):
    """``Pose3D()``, ``Pose3D(x, y, z)``, ``Pose3D(x, y, z, t, p, s)``, ``Pose3D(x, y, z, t, p, s, w)``.

    Orientation: theta about z, then phi about y, then psi about x.
    """

    __slots__ = ()
    _msg_type = _MessageType('Pose3D')
    _fields = ('x', 'y', 'z', 'theta', 'phi', 'psi', 'weight')

    @classmethod
    def _positional(cls, count: int) -> tuple[str, ...]:
        if count not in (0, 3, 6, 7):
            raise TypeError('Pose3D takes (), (x, y, z), (x, y, z, t, p, s) or (x, y, z, t, p, s, w)')
        return cls._fields[:count]

    def phi(self, value: Any = _UNSET) -> Any:
        """Read phi, or set it when given a value.

        :param value: the new phi, rad about y; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('phi', value)

    def psi(self, value: Any = _UNSET) -> Any:
        """Read psi, or set it when given a value.

        :param value: the new psi, rad about x; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('psi', value)


class CVector(_View):
    """A Cartesian 2-D vector: ``CVector(x, y)``."""

    __slots__ = ()
    _msg_type = _MessageType('CVector')
    _fields = ('x', 'y')

    def x(self, value: Any = _UNSET) -> Any:
        """Read x, or set it when given a value.

        :param value: the new x; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('x', value)

    def y(self, value: Any = _UNSET) -> Any:
        """Read y, or set it when given a value.

        :param value: the new y; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('y', value)


class PVector(_View):
    """A polar 2-D vector: ``PVector(magnitude, angle)``."""

    __slots__ = ()
    _msg_type = _MessageType('PVector')
    _fields = ('magnitude', 'angle')

    def magnitude(self, value: Any = _UNSET) -> Any:
        """Read the magnitude, or set it when given a value.

        :param value: the new magnitude; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('magnitude', value)

    def angle(self, value: Any = _UNSET) -> Any:
        """Read the angle, or set it when given a value.

        :param value: the new angle, rad; omitted: read it.
        :returns: the value read, or None after a write.
        """
        return self._access('angle', value)


#: View classes by WURDE type name.
GEOMETRY: dict[str, type[_View]] = {
    'Point': PlanarPoint, 'Point3D': Point3D, 'Pose': PlanarPose, 'Pose3D': Pose3D,
    'CVector': CVector, 'PVector': PVector,
}
