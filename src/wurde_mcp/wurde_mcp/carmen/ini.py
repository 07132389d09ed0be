"""carmen.ini: CARMEN's parameter file, read for ``param_daemon`` and ``param_tool install``.

::

    # comment lines, and trailing comments after a value
    [*]                          # every robot
    robot_max_t_vel    0.5       # module "robot", variable "max_t_vel"
    laser_flipped      off

    [pluto]                      # this robot: overrides [*]
    robot_max_t_vel    0.3

A line is ``module_variable value``: the module is the text before the first ``_``, the variable
the rest (letters, digits and ``_``); the value is the rest of the line, trimmed, up to a ``#``.
Everything wrong — a line outside any section, a name without a value, a section header that is
not ``[*]`` or ``[robot]``, a name without ``_``, a name twice in one section, bytes that are not
UTF-8 — is a :class:`~wurde_idl.errors.ConfigError` naming file, line and reason.
``$include`` lines are not supported: they are refused as a malformed name.
"""

from __future__ import annotations

import os
import pathlib
import re
from dataclasses import dataclass, field

from wurde_idl.errors import ConfigError

__all__ = ['ALL_ROBOTS', 'SEARCH_PATH', 'Entry', 'IniFile', 'choose_robot', 'find_ini', 'read_ini',
           'robots']

#: The section whose parameters every robot has.
ALL_ROBOTS = '*'
#: Where ``param_daemon`` looks for carmen.ini when it is given none (CARMEN's param_daemon:
#: the working directory, its parent, the parent's ``src``).
SEARCH_PATH = ('carmen.ini', '../carmen.ini', '../src/carmen.ini')

_SECTION = re.compile(r'\[([^\[\]\s]+)\]')
_NAME = re.compile(r'[A-Za-z0-9_]+')


@dataclass(frozen=True)
class Entry:
    """One ``module_variable value`` line."""

    module: str
    variable: str
    value: str
    path: str
    line: int

    @property
    def name(self) -> str:
        """CARMEN's fully qualified name, ``module_variable``."""
        return f'{self.module}_{self.variable}'


@dataclass
class IniFile:
    """A read carmen.ini: its sections in file order, each ``{module_variable: Entry}``."""

    path: str
    sections: dict[str, dict[str, Entry]] = field(default_factory=dict)

    def robots(self) -> list[str]:
        """The robot sections (every section but ``[*]``), in file order."""
        return [name for name in self.sections if name != ALL_ROBOTS]

    def parameters(self, robot: str | None) -> dict[str, Entry]:
        """The parameters of ``robot``: ``[*]``'s, overridden by ``[robot]``'s (``None``: ``[*]``
        only), sorted by name.

        :raises ConfigError: for a robot the file has no section of.
        """
        if robot is not None and robot not in self.robots():
            raise ConfigError(self.path, None, f'no robot [{robot}] (robots: {_listing(self)})')
        merged = dict(self.sections.get(ALL_ROBOTS, {}))
        if robot is not None:
            merged.update(self.sections[robot])
        return dict(sorted(merged.items()))


def _listing(ini: IniFile) -> str:
    return ', '.join(ini.robots()) or 'none'


def read_ini(path: str | os.PathLike[str]) -> IniFile:
    """Read one carmen.ini.

    :raises ConfigError: with file, line and reason for anything the module docstring refuses;
        an unreadable file is a ConfigError without a line.
    """
    path = os.fspath(path)
    try:
        data = pathlib.Path(path).read_bytes()
    except OSError as error:
        raise ConfigError(path, None, f'cannot read: {error.strerror}') from error
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as error:
        line = data[:error.start].count(b'\n') + 1
        raise ConfigError(path, line, f'not UTF-8 (byte 0x{data[error.start]:02x})') from error
    ini = IniFile(path)
    section: dict[str, Entry] | None = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split('#', 1)[0].strip()
        if not line:
            continue
        if line.startswith('['):
            found = _SECTION.fullmatch(line)
            if not found:
                raise ConfigError(path, number, f'section header {line!r} is not [*] or [robot]')
            section = ini.sections.setdefault(found.group(1), {})
            continue
        if section is None:
            raise ConfigError(path, number, f'{line.split()[0]!r} is outside any section '
                                            '(start with [*] or [robot])')
        entry = _entry(path, number, line)
        if entry.name in section:
            raise ConfigError(path, number, f'{entry.name} is set twice in this section '
                                            f'(first on line {section[entry.name].line})')
        section[entry.name] = entry
    return ini


def _entry(path: str, number: int, line: str) -> Entry:
    parts = line.split(None, 1)
    name = parts[0]
    if not _NAME.fullmatch(name):
        raise ConfigError(path, number, f'name {name!r} has characters other than letters, '
                                        'digits and _')
    module, _, variable = name.partition('_')
    if not module or not variable:
        raise ConfigError(path, number, f'name {name!r} is not module_variable (it needs a _ '
                                        'between a module and a variable)')
    if len(parts) < 2:
        raise ConfigError(path, number, f'{name} has no value')
    return Entry(module, variable, parts[1].strip(), path, number)


def find_ini(directory: str | os.PathLike[str] = '.') -> str:
    """The carmen.ini ``param_daemon`` reads when it is given none: the first of
    :data:`SEARCH_PATH` from ``directory`` that exists.

    :raises ConfigError: naming every place looked at, when there is none.
    """
    for candidate in SEARCH_PATH:
        path = pathlib.Path(directory) / candidate
        if path.is_file():
            return os.path.abspath(path)
    raise ConfigError('carmen.ini', None, 'no carmen.ini given and none found at '
                      + ', '.join(SEARCH_PATH) + f' (from {os.path.abspath(directory)})')


def robots(path: str | os.PathLike[str]) -> list[str]:
    """The robot sections of the carmen.ini at ``path`` (not ``[*]``), in file order.

    :raises ConfigError: when the file is refused.
    """
    return read_ini(path).robots()


def choose_robot(ini: IniFile, robot: str | None) -> str | None:
    """The robot whose parameters to serve: ``robot`` if given (it must have a section), else
    the only robot section, else ``None`` when there is only ``[*]``.

    CARMEN's param_daemon asks which robot when the file has several; a daemon started by the
    MCP cannot be asked, so this refuses instead, listing the robots.

    :raises ConfigError: for an unknown robot, or several robots and none chosen.
    """
    names = ini.robots()
    if robot is not None:
        if robot not in names:
            raise ConfigError(ini.path, None, f'no robot [{robot}] (robots: {_listing(ini)})')
        return robot
    if len(names) > 1:
        raise ConfigError(ini.path, None, f'{len(names)} robots ({", ".join(names)}): choose one '
                                          'with -R ROBOT')
    return names[0] if names else None
