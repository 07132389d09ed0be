"""The WURDE type names of interface files and the ROS 2 types they become.

Seed: WURDE Programming Guide 3.1 and 3.3 (the supported types: Byte, Integer, Long, String,
Float, Double, Bool, Pose, Pose3D, CVector, PVector, Point, Point3D, RunState, ProcessLocale,
ProcessType, StatusMode, ConnectionStrategy).  ``Boolean`` is accepted for ``Bool`` because the
guide's own example uses it.  Byte is unsigned (``uint8``), as the guide announces it will become.
"""

from __future__ import annotations

from dataclasses import dataclass

#: Package that defines the built-in composite types and the common header.
BUILTIN_PACKAGE = 'wurde_interfaces'


@dataclass(frozen=True)
class ScalarType:
    """A primitive WURDE type and its ROS 2 ``.msg`` spelling."""

    name: str
    ros_type: str
    integral: bool = False


SCALARS: dict[str, ScalarType] = {
    'Byte': ScalarType('Byte', 'uint8', integral=True),
    'Integer': ScalarType('Integer', 'int32', integral=True),
    'Long': ScalarType('Long', 'int64', integral=True),
    'String': ScalarType('String', 'string'),
    'Float': ScalarType('Float', 'float32'),
    'Double': ScalarType('Double', 'float64'),
    'Bool': ScalarType('Bool', 'bool'),
}

#: Spellings the seed uses for the same type.
ALIASES: dict[str, str] = {'Boolean': 'Bool'}

#: Built-in composite types (``msg/<Name>.msg`` of :data:`BUILTIN_PACKAGE`) and their fields.
BUILTIN_MESSAGES: dict[str, tuple[str, ...]] = {
    'Point': ('x', 'y', 'weight'),
    'Point3D': ('x', 'y', 'z', 'weight'),
    'Pose': ('x', 'y', 'theta', 'weight'),
    'Pose3D': ('x', 'y', 'z', 'theta', 'phi', 'psi', 'weight'),
    'CVector': ('x', 'y'),
    'PVector': ('magnitude', 'angle'),
}

#: Built-in enumerations (a ``uint8 value`` plus named constants) and their values, in order.
BUILTIN_ENUMS: dict[str, tuple[str, ...]] = {
    'RunState': ('RUN', 'IDLE', 'RESET', 'RESTART', 'QUIT'),
    'ProcessLocale': ('INTERNAL', 'EXTERNAL'),
    'ProcessType': ('MANAGED', 'UNMANAGED', 'CRITICAL'),
    'StatusMode': ('UNKNOWN', 'STARTING', 'ACTIVE', 'ZOMBIE', 'DEAD', 'FAILED'),
    'ConnectionStrategy': ('NORMAL', 'ASSIGNED', 'AUTO'),
}

#: Every type name an interface file may use without defining it.
BUILTIN_TYPE_NAMES = frozenset(SCALARS) | frozenset(ALIASES) | frozenset(BUILTIN_MESSAGES) | \
    frozenset(BUILTIN_ENUMS)

#: Messages of :data:`BUILTIN_PACKAGE` that are not WURDE types but part of every Data/Info message.
SUPPORT_MESSAGES = ('Header', 'Lock')


def canonical(type_name: str) -> str:
    """Return the canonical spelling of a WURDE type name (``Boolean`` -> ``Bool``).

    :param type_name: a type name as an interface file writes it; any other name comes back as
        it is.
    """
    return ALIASES.get(type_name, type_name)
