"""Variables that clients make: a ``var`` assignment to a new name, and the copies of another
server's variables (``cam varpush struct=gmk cmd="var gmk copy"``, AU Robot Servers, "Get value
to another server").

AURS adds an unknown variable on assignment, with the default type of ``type=`` and the
description "new"; a copied variable is "added" to the special structure ``VAR`` (or where
``dest=`` says).  :class:`UserVariables` does both on this server's pool, but never over one of
the robot's own variables, and at most ``limit`` of them, so that no client can grow the pool
without bound.
"""

from __future__ import annotations

from .command import NAME
from .variables import TYPES, Value, VarError, Variable, VariablePool, parse_value

__all__ = ['COPY_STRUCT', 'UserVariables']

#: Where copies from another server go unless ``dest=`` says otherwise (the seed: ``var var.gmk``).
COPY_STRUCT = 'var'

#: The AURS ``type=`` names and the typ they become here (AURS's ``3d``, ``dq`` and ``t`` are
#: doubles with no extra attributes in this server).
TYPE_NAMES = {'d': 'd', 'pose': 'pose', 'm2': 'm2', 's': 's', '3d': 'd', 'dq': 'd', 't': 'd'}


class UserVariables:
    """The client-made variables of one pool."""

    def __init__(self, pool: VariablePool, limit: int = 1000) -> None:
        self._pool = pool
        self._limit = limit
        self._names: set[str] = set()

    def owns(self, name: str) -> bool:
        """Whether ``name`` is a variable a client made."""
        return name.lower() in self._names

    def robot_struct(self, name: str) -> str:
        """The structure above ``name`` that holds robot variables, '' if none does: clients make
        no variables in the robot's structures."""
        parts = name.lower().split('.')
        for depth in range(len(parts) - 1, 0, -1):
            prefix = '.'.join(parts[:depth])
            if any(not self.owns(var.name) for var in self._pool.variables(prefix)):
                return self._pool.struct_name(prefix)
        return ''

    def put(self, name: str, typ: str, text: str, description: str,
            struct_description: str = 'new') -> tuple[Value | None, Variable]:
        """Make or update variable ``name`` of type ``typ`` from ``text``: (its old value or None
        when it is new, the variable).

        :raises VarError: a bad name, type or value, a robot variable or a structure of that name,
            or ``limit`` variables made already.
        """
        if not NAME.fullmatch(name) or name.startswith('.') or name.endswith('.') or '..' in name:
            raise VarError(f'"{name}" is not a variable name')
        asked, typ = typ, TYPE_NAMES.get(typ.lower(), '')
        if typ not in TYPES:
            raise VarError(f'type={asked} is not one of {", ".join(TYPE_NAMES)}')
        var = self._pool.find(name)
        if var is not None and not self.owns(name):
            raise VarError(f'{var.name} belongs to the robot: not replaced')
        robot = self.robot_struct(name)
        if var is None and robot:
            raise VarError(f'not found - try: var help ({robot} is the robot\'s structure)')
        if var is None and self._pool.is_struct(name):
            raise VarError(f'{self._pool.struct_name(name)} is a structure')
        value = parse_value(typ if var is None else var.typ, text)
        if var is not None:
            old = var.current()
            self._pool.update(var.name, value)
            return old, var
        if len(self._names) >= self._limit:
            raise VarError(f'too many variables made by clients (max {self._limit})')
        parts = name.split('.')
        for depth in range(1, len(parts)):
            struct = '.'.join(parts[:depth])
            if not self._pool.is_struct(struct):
                self._pool.describe(struct, struct_description)
        var = self._pool.add(Variable(name, typ, description, value))
        self._names.add(name.lower())
        self._pool.touch(name)
        return None, var
