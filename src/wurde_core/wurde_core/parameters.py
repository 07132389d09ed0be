"""A module's WURDE options and configuration as ROS 2 parameters of its node, and its tunables.

Every module's node serves parameters (``ros2 param list /PlutoLaser``), with one mapping for
all modules, from what the guide's options and role configuration (5.1.1-5.1.4) gave it:

==============================  ==========================================================
``wurde.module``                the CommsManager's name (after ``-n``)
``wurde.role_config``           the role-config file read (``-g`` or ``role-config.xml``), or ''
``wurde.<setting>``             data_directory, config_directory, bin_directory, log_directory,
                                log_level, mcp_config, mcp_mappings: as the getters give them
                                (file, then the WURDE_* environment)
``wurde.option.<name>``         each global option: the file's ``<option>`` and the command
                                line's user options (``-c 3`` is ``wurde.option.c``)
``wurde.module_option.<name>``  this module's ``<module name><option>`` values
``use_sim_time``                rclpy's own: stamps and clocks from ``/clock``
==============================  ==========================================================

These are read-only (their descriptors say so): they were read once at start, and the program
went its way with them; a ``--params-file`` naming them is accepted and leaves them as they are,
so that ``ros2 param dump`` gives a file the module takes back.  Option names that are not legal
in a parameter name have each such character replaced by ``_``.

A module adds what may change while it runs with :meth:`Tunables.declare` (through
``CommsManager.tunable``): a writable, typed parameter with a range, whose current value the
program reads from the returned :class:`Tunable`; ``--params-file`` and ``ros2 param set`` reach
it.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from typing import Any

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor

from .role_config import RoleConfiguration

PREFIX = 'wurde.'
_SETTINGS = ('data_directory', 'config_directory', 'bin_directory', 'log_directory', 'log_level',
             'mcp_config', 'mcp_mappings')
_ILLEGAL = re.compile(r'[^A-Za-z0-9_]')


def parameter_name(*parts: str) -> str:
    """``wurde.<part>.<part>``, each part made legal (``_`` for any other character)."""
    return PREFIX + '.'.join(_ILLEGAL.sub('_', part) or '_' for part in parts)


def configuration_values(module: str, config: RoleConfiguration) -> dict[str, str]:
    """The read-only parameters of the mapping above, by name."""
    values = {parameter_name('module'): module,
              parameter_name('role_config'): config.path or ''}
    for setting in _SETTINGS:
        values[parameter_name(setting)] = getattr(config, f'get_{_getter(setting)}')()
    for name, value in config.options().items():
        values[parameter_name('option', name)] = value
    for name, value in config.module_options(module).items():
        values[parameter_name('module_option', name)] = value
    return values


def _getter(setting: str) -> str:
    return {'mcp_config': 'mcp_config_file', 'mcp_mappings': 'mcp_mappings_file'}.get(setting,
                                                                                      setting)


def declare_configuration(node: Any, module: str, config: RoleConfiguration) -> None:
    """Declare the mapping's parameters on ``node``, read-only."""
    for name, value in configuration_values(module, config).items():
        descriptor = ParameterDescriptor(
            description='WURDE configuration, read at start (see wurde_core.parameters)',
            read_only=True)
        node.declare_parameter(name, value, descriptor, ignore_override=True)


@dataclass
class Tunable:
    """A value the program reads while it runs and a user may set (``ros2 param set``)."""

    name: str
    default: bool | int | float | str
    description: str
    minimum: float | None = None
    maximum: float | None = None
    _node: Any = None

    @property
    def value(self) -> Any:
        """The current value (the default until the module's node exists)."""
        if self._node is None:
            return self.default
        return self._node.get_parameter(self.name).value

    def descriptor(self) -> ParameterDescriptor:
        """Its description, and its range when it has one.

        :raises TypeError: for a range on a value that is not a number.
        """
        descriptor = ParameterDescriptor(description=self.description)
        if self.minimum is None and self.maximum is None:
            return descriptor
        if isinstance(self.default, bool) or not isinstance(self.default, (int, float)):
            raise TypeError(f'tunable {self.name}: a range needs a number')
        if isinstance(self.default, int):
            descriptor.integer_range = [IntegerRange(
                from_value=-2**63 if self.minimum is None else int(self.minimum),
                to_value=2**63 - 1 if self.maximum is None else int(self.maximum))]
        else:
            descriptor.floating_point_range = [FloatingPointRange(
                from_value=-sys.float_info.max if self.minimum is None else float(self.minimum),
                to_value=sys.float_info.max if self.maximum is None else float(self.maximum))]
        return descriptor


class Tunables:
    """The tunables of one module: declared on its node as soon as there is one."""

    def __init__(self) -> None:
        self._tunables: dict[str, Tunable] = {}
        self._node: Any = None

    def declare(self, name: str, default: bool | int | float | str, description: str,
                minimum: float | None = None, maximum: float | None = None) -> Tunable:
        """A writable parameter ``name`` (no ``wurde.`` prefix: that is the configuration's).

        :raises ValueError: for a name declared twice or inside ``wurde.``.
        """
        if name in self._tunables or name.startswith(PREFIX):
            raise ValueError(f'tunable {name}: declared twice or inside "{PREFIX}"')
        tunable = Tunable(name, default, description, minimum, maximum)
        tunable.descriptor()  # a range on a non-number is refused now, not at the node
        self._tunables[name] = tunable
        if self._node is not None:
            self._bind(tunable)
        return tunable

    def attach(self, node: Any) -> None:
        """Declare every tunable on ``node`` (a ``--params-file`` value wins over the default)."""
        self._node = node
        for tunable in self._tunables.values():
            self._bind(tunable)

    def _bind(self, tunable: Tunable) -> None:
        self._node.declare_parameter(tunable.name, tunable.default, tunable.descriptor())
        tunable._node = self._node
