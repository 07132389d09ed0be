"""A module's WURDE options and configuration as ROS 2 parameters of its node, and its tunables.

Every module's node serves parameters (``ros2 param list /PlutoLaser``), with one mapping for
all modules, from what the guide's options and role configuration (5.1.1-5.1.4) gave it:
``wurde.module``, ``wurde.role_config``, ``wurde.<setting>`` for each getter's value,
``wurde.option.<name>`` and ``wurde.module_option.<name>`` (docs/ros2.md, "Using it from ROS 2",
lists them).  These are read-only (their descriptors say so): they were read once at start, and
the program went its way with them; a ``--params-file`` naming them is accepted and leaves them as
they are, so that ``ros2 param dump`` gives a file the module takes back.  Option names that are
not legal in a parameter name have each such character replaced by ``_``.

A module adds what may change while it runs with :meth:`Tunables.declare` (through
``CommsManager.tunable``): a writable, typed parameter with a range, whose current value the
program reads from the returned :class:`Tunable`; ``--params-file`` and ``ros2 param set`` reach
it.  :class:`TunedSettings` makes chosen fields of a settings dataclass tunables in one step.
"""

from __future__ import annotations

import dataclasses
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
from rclpy.parameter import Parameter

from .role_config import RoleConfiguration

PREFIX = 'wurde.'
_SETTINGS = ('data_directory', 'config_directory', 'bin_directory', 'log_directory', 'log_level',
             'mcp_config', 'mcp_mappings')
_ILLEGAL = re.compile(r'[^A-Za-z0-9_]')


def parameter_name(*parts: str) -> str:
    """``wurde.<part>.<part>``, each part made legal (``_`` for any other character)."""
    return PREFIX + '.'.join(_ILLEGAL.sub('_', part) or '_' for part in parts)


def configuration_values(module: str, config: RoleConfiguration) -> dict[str, str]:
    """The read-only parameters of the mapping above, by name.

    :param module: the module's name (after ``-n``); also selects its ``<module>`` options.
    :param config: the configuration read at start.
    """
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
    """Declare the mapping's parameters on ``node``, read-only (a ``--params-file`` value for
    one is ignored).

    :param node: the module's rclpy node.
    :param module: the module's name.
    :param config: the configuration read at start.
    """
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


#: A check of new tunable values ({name: value} of those being set): the reason to refuse them,
#: or None.
Check = Callable[[dict[str, Any]], 'str | None']


class Tunables:
    """The tunables of one module: declared on its node as soon as there is one."""

    def __init__(self) -> None:
        self._tunables: dict[str, Tunable] = {}
        self._checks: list[Check] = []
        self._node: Any = None

    def add_check(self, check: Check) -> None:
        """Refuse a ``ros2 param set`` that ``check`` finds wrong (values that only make sense
        together, such as a slow-down distance beyond the stop distance).

        :param check: called with ``{name: value}`` of the tunables being set (not called when
            none is); returns the reason to refuse, or None.
        """
        self._checks.append(check)

    def _on_set(self, parameters: list[Any]) -> SetParametersResult:
        values = {p.name: p.value for p in parameters if p.name in self._tunables}
        for check in self._checks:
            reason = check(values) if values else None
            if reason:
                return SetParametersResult(successful=False, reason=reason)
        return SetParametersResult(successful=True)

    def declare(self, name: str, default: bool | int | float | str, description: str,
                minimum: float | None = None, maximum: float | None = None) -> Tunable:
        """A writable parameter ``name``, declared on the node now or when it is attached.

        :param name: the parameter's name (no ``wurde.`` prefix: that is the configuration's).
        :param default: the starting value; its type is the parameter's.
        :param description: the descriptor's text.
        :param minimum: the lowest value, for a number (an int's bound is made an int); None:
            unbounded.
        :param maximum: the highest value, for a number; None: unbounded.
        :raises ValueError: for a name declared twice or inside ``wurde.``.
        :raises TypeError: for a bound on a value that is not a number.
        """
        if name in self._tunables or name.startswith(PREFIX):
            raise ValueError(f'tunable {name}: declared twice or inside "{PREFIX}"')
        tunable = Tunable(name, default, description, minimum, maximum)
        tunable.descriptor()  # a range on a non-number is refused now, not at the node
        self._tunables[name] = tunable
        if self._node is not None:
            self._bind(tunable)
        return tunable

    def items(self) -> list[Tunable]:
        """Every tunable declared, in order."""
        return list(self._tunables.values())

    def set(self, name: str, value: Any) -> str | None:
        """Set tunable ``name`` on the node as ``ros2 param set`` would (its range and the checks
        apply).

        :param name: a declared tunable's name.
        :param value: the new value, of the tunable's type.
        :returns: the reason it was refused, or None when it was taken.
        """
        if self._node is None:
            return 'the module has no node yet'
        result = self._node.set_parameters([Parameter(name, value=value)])[0]
        return None if result.successful else (result.reason or 'refused')

    def attach(self, node: Any) -> None:
        """Declare every tunable on ``node`` (a ``--params-file`` value wins over the default);
        later declarations go straight to it.

        :param node: the module's rclpy node.
        """
        self._node = node
        node.add_on_set_parameters_callback(self._on_set)
        for tunable in self._tunables.values():
            self._bind(tunable)

    def _bind(self, tunable: Tunable) -> None:
        self._node.declare_parameter(tunable.name, tunable.default, tunable.descriptor())
        tunable._node = self._node


def out_of_range(settings: Any, fields: dict[str, tuple[str, float | None, float | None]],
                 prefix: str = '') -> str | None:
    """Why ``settings`` cannot start :class:`TunedSettings` with ``fields`` (a value outside
    its tunable's range, which the node would refuse), or None: for checking options first.

    :param settings: the settings object (any object with those fields as attributes).
    :param fields: field -> (description, minimum, maximum), as for :class:`TunedSettings`.
    :param prefix: put before the field's name in the reason (the tunables' prefix).
    """
    for name, (_text, low, high) in fields.items():
        value = getattr(settings, name)
        if (low is not None and value < low) or (high is not None and value > high):
            return f'{prefix}{name} = {value} is out of range [{low}, {high}]'
    return None


class TunedSettings:
    """A frozen dataclass of a module's settings whose chosen fields are tunables.

    ``fields`` maps a field to (description, minimum, maximum); each becomes the tunable
    ``<prefix><field>``, starting from the settings given.  :meth:`current` returns the settings
    with the tunables' present values — the same object until a user changes one — so a loop
    reads ``tuned.current()`` where it used its settings.
    """

    def __init__(self, manager: Any, settings: Any,
                 fields: Mapping[str, tuple[str, float | None, float | None]], prefix: str = '') -> None:
        """Declare the tunables on ``manager`` and a check that runs the settings' own validation.

        :param manager: the module's CommsManager.
        :param settings: the starting settings, a frozen dataclass.
        :param fields: field -> (description, minimum, maximum); None for an open bound.
        :param prefix: put before each field's name to make the tunable's (``"goto."``).
        """
        self._settings = settings
        self._prefix = prefix
        self._tunables = {name: manager.tunable(prefix + name, getattr(settings, name), text, low, high)
                          for name, (text, low, high) in fields.items()}
        manager.check_tunables(self._check)

    def _check(self, values: dict[str, Any]) -> str | None:
        """The settings' own validation (``__post_init__``) of the values being set."""
        mine = {name: values[self._prefix + name] for name in self._tunables
                if self._prefix + name in values}
        if not mine:
            return None
        try:
            dataclasses.replace(self.current(), **mine)
        except (ValueError, TypeError) as error:
            return str(error)
        return None

    def current(self) -> Any:
        """The settings with the tunables' present values (the same object until one changes)."""
        values = {name: tunable.value for name, tunable in self._tunables.items()}
        if any(getattr(self._settings, name) != value for name, value in values.items()):
            self._settings = dataclasses.replace(self._settings, **values)
        return self._settings
