"""carmen.ini: CARMEN's parameter file, read by CARMEN's rules for ``param_daemon`` and
``param_tool install``.

The rules are those of CARMEN's ``param_daemon.c`` (``read_parameters_from_file``,
``set_param``, ``find_valid_robots``; Programming with CARMEN, the parameter daemon), so that
CARMEN's own carmen.ini and robots' files load: ``[*]``, ``[expert]`` and ``[ROBOT]`` sections,
``module_variable value`` lines, ``#`` comments, the sections that apply read in file order and
a later line winning.  docs/wurde-mcp.md ("carmen.ini") lists every rule, what is skipped with a
warning and where this reader deviates from CARMEN's.

Before changing it: what CARMEN's daemon skips, this reader skips too, with an
:class:`IniWarning` naming file:line and the reason (each once, in :attr:`IniFile.warnings`);
it also warns where a line is read as CARMEN reads it but probably not as its author meant.
A parameter name must be a ROS 2 parameter name (letters, digits and ``_``), where CARMEN takes
any characters.  A file that cannot be read or is not UTF-8 is refused as a
:class:`~wurde_idl.errors.ConfigError`.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import re
from dataclasses import dataclass, field

from wurde_idl.errors import ConfigError

__all__ = ['ALL_ROBOTS', 'EXPERT', 'SEARCH_PATH', 'Entry', 'IniFile', 'IniWarning', 'Section',
           'choose_robot', 'find_ini', 'read_ini', 'robots']

#: The section whose parameters every robot has.
ALL_ROBOTS = '*'
#: The section of parameters every robot has, marked expert (CARMEN's PARAM_LEVEL_EXPERT).
EXPERT = 'expert'
#: Where ``param_daemon`` looks for carmen.ini when it is given none (CARMEN's param_daemon:
#: the working directory, its parent, the parent's ``src``).
SEARCH_PATH = ('carmen.ini', '../carmen.ini', '../src/carmen.ini')

#: A name ROS 2 tools take as a parameter name once its first ``_`` is a ``.``.
_NAME = re.compile(r'[A-Za-z0-9_]+')
#: CARMEN's longest parameter name (``lvalue[255]``); a longer one is skipped with a warning.
_LONGEST_NAME = 254


@dataclass(frozen=True)
class Entry:
    """One ``module_variable value`` line."""

    module: str
    variable: str
    value: str
    path: str
    line: int
    #: From the ``[expert]`` section.
    expert: bool = False

    @property
    def name(self) -> str:
        """CARMEN's fully qualified name, ``module_variable``."""
        return f'{self.module}_{self.variable}'


@dataclass(frozen=True)
class IniWarning:
    """A line read as CARMEN reads it, though probably not as meant: file, line and reason."""

    path: str
    line: int
    reason: str

    def __str__(self) -> str:
        return f'{self.path}:{self.line}: {self.reason}'


@dataclass
class Section:
    """One section header and its lines, in file order."""

    #: ``*``, ``expert`` (as spelled) or a robot's name (as spelled).
    name: str
    line: int
    entries: list[Entry] = field(default_factory=list)

    @property
    def for_every_robot(self) -> bool:
        """``[*]`` or ``[expert]``: its parameters are every robot's."""
        return self.name == ALL_ROBOTS or self.name.lower() == EXPERT

    def applies_to(self, robot: str | None) -> bool:
        """Whether the parameters of ``robot`` include this section's.

        :param robot: a robot's name, in any case (``None``: none chosen).
        """
        return self.for_every_robot or (robot is not None and self.name.lower() == robot.lower())


@dataclass
class IniFile:
    """A read carmen.ini: its sections in file order and what was warned about."""

    path: str
    sections: list[Section] = field(default_factory=list)
    warnings: list[IniWarning] = field(default_factory=list)

    def robots(self) -> list[str]:
        """The robots (every section but ``[*]`` and ``[expert]``), in file order, each once (in
        its first spelling)."""
        names: dict[str, str] = {}
        for section in self.sections:
            if not section.for_every_robot:
                names.setdefault(section.name.lower(), section.name)
        return list(names.values())

    def robot(self, name: str) -> str:
        """The file's spelling of robot ``name`` (any case).

        :param name: a robot's name, in any case.
        :raises ConfigError: for a robot the file has no section of.
        """
        for robot in self.robots():
            if robot.lower() == name.lower():
                return robot
        raise ConfigError(self.path, None, f'no robot [{name}] (robots: {_listing(self)})')

    def parameters(self, robot: str | None) -> dict[str, Entry]:
        """The parameters of ``robot`` (``None``: ``[*]`` and ``[expert]`` only), sorted by name:
        the sections that apply, in file order, a later line winning.

        :param robot: a robot's name, in any case (``None``: ``[*]`` and ``[expert]`` only).
        :returns: the entries by ``module_variable`` name, as the file first spells it.
        :raises ConfigError: for a robot the file has no section of.
        """
        if robot is not None:
            robot = self.robot(robot)
        merged: dict[str, Entry] = {}
        for section in self.sections:
            if not section.applies_to(robot):
                continue
            for entry in section.entries:
                first = merged.get(entry.name.lower())
                if first is not None and first.name != entry.name:   # CARMEN keeps the first name
                    entry = dataclasses.replace(entry, module=first.module, variable=first.variable)
                merged[entry.name.lower()] = entry
        return {entry.name: entry for entry in sorted(merged.values(), key=lambda e: e.name)}


def _listing(ini: IniFile) -> str:
    return ', '.join(ini.robots()) or 'none'


def read_ini(path: str | os.PathLike[str]) -> IniFile:
    """Read one carmen.ini by CARMEN's rules (docs/wurde-mcp.md, "carmen.ini").

    :param path: the file.
    :returns: its sections and the warnings about lines skipped or probably misread.
    :raises ConfigError: for a file that cannot be read (no line) or that is not UTF-8 (its line).
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
    reader = _Reader(IniFile(path))
    for number, raw in enumerate(text.splitlines(), start=1):
        reader.line(number, raw)
    return reader.ini


class _Reader:
    """CARMEN's reading rules, line by line, into an :class:`IniFile`."""

    def __init__(self, ini: IniFile) -> None:
        self.ini = ini
        self.section: Section | None = None
        self.skipping = False                   # under a header that names no section
        self.outside_warned = False
        self.set_in: dict[tuple[str, str], int] = {}    # (section, name) -> line, lower case
        self.spelling: dict[str, Entry] = {}            # name (lower case) -> its first entry
        self.by_robot: dict[str, list[str]] = {}       # name -> '[robot] line N' it is set in

    def warn(self, line: int, reason: str) -> None:
        self.ini.warnings.append(IniWarning(self.ini.path, line, reason))

    def line(self, number: int, raw: str) -> None:
        text = raw.split('#', 1)[0].strip()
        if not text:
            return
        if text.startswith('['):
            self.header(number, text)
        elif self.section is not None:
            self.entry(number, text)
        elif not self.skipping and not self.outside_warned:
            self.outside_warned = True
            self.warn(number, f'{text.split()[0]!r} is before the first section header: it and '
                              'the lines up to the header are skipped')

    def header(self, number: int, text: str) -> None:
        word = text.split(None, 1)[0]
        name, bracket, after = word[1:].partition(']')
        if not bracket or not name:
            self.section, self.skipping = None, True
            self.warn(number, f'section header {text!r} is not [*], [expert] or [robot]: the '
                              'lines under it are skipped')
            return
        if after or text[len(word):].strip():
            self.warn(number, f'text after [{name}] is ignored')
        if name.startswith(ALL_ROBOTS) and name != ALL_ROBOTS:
            self.warn(number, f'[{name}] is taken as [*], as CARMEN takes it')
            name = ALL_ROBOTS
        self.section, self.skipping = Section(name, number), False
        self.ini.sections.append(self.section)

    def entry(self, number: int, text: str) -> None:
        assert self.section is not None
        parts = text.split(None, 1)
        name = parts[0]
        if len(parts) < 2:
            self.warn(number, f'{name} has no value: skipped')
            return
        module, _, variable = name.partition('_')
        if not module or not variable:
            self.warn(number, f'name {name!r} is not module_variable (it needs a _ between a '
                              'module and a variable): skipped')
            return
        if len(name) > _LONGEST_NAME or not _NAME.fullmatch(name):
            self.warn(number, f'name {name[:40]!r} has characters other than letters, digits and _ '
                              'or more than 254 of them (a ROS 2 parameter name here): skipped')
            return
        section = self.section
        entry = Entry(module, variable, parts[1].strip(), self.ini.path, number,
                      expert=section.name.lower() == EXPERT)
        self.check(section, entry)
        section.entries.append(entry)

    def check(self, section: Section, entry: Entry) -> None:
        """Warn where CARMEN's reading (a later line wins, names in any case) may surprise."""
        key, number = entry.name.lower(), entry.line
        first = self.spelling.setdefault(key, entry)
        if first.name != entry.name:
            self.warn(number, f'{entry.name} is {first.name} of line {first.line} (names are not '
                              f'case sensitive): served as {first.name}')
        earlier = self.set_in.get((section.name.lower(), key))
        if earlier is not None:
            self.warn(number, f'{entry.name} is set again in [{section.name}] (first on line '
                              f'{earlier}): this later value wins')
        self.set_in[(section.name.lower(), key)] = number
        if not section.for_every_robot:
            self.by_robot.setdefault(key, []).append(f'[{section.name}] line {number}')
        elif key in self.by_robot:
            self.warn(number, f'{entry.name} of [{section.name}] overrides '
                              f'{", ".join(self.by_robot.pop(key))}: the later line wins')


def find_ini(directory: str | os.PathLike[str] = '.') -> str:
    """The carmen.ini ``param_daemon`` reads when it is given none: the first of
    :data:`SEARCH_PATH` from ``directory`` that exists.

    :param directory: where the search starts (the working directory by default).
    :returns: the absolute path of the file found.
    :raises ConfigError: naming every place looked at, when there is none.
    """
    for candidate in SEARCH_PATH:
        path = pathlib.Path(directory) / candidate
        if path.is_file():
            return os.path.abspath(path)
    raise ConfigError('carmen.ini', None, 'no carmen.ini given and none found at '
                      + ', '.join(SEARCH_PATH) + f' (from {os.path.abspath(directory)})')


def robots(path: str | os.PathLike[str]) -> list[str]:
    """The robot sections of the carmen.ini at ``path`` (not ``[*]`` nor ``[expert]``), in file
    order.

    :param path: the carmen.ini.
    :raises ConfigError: when the file is refused.
    """
    return read_ini(path).robots()


def choose_robot(ini: IniFile, robot: str | None) -> str | None:
    """The robot whose parameters to serve, spelled as the file spells it: ``robot`` if given
    (any case; it must have a section), else the only robot section, else ``None`` when there is
    none (``[*]`` and ``[expert]`` only: CARMEN's "default robot").

    With several robots and none chosen CARMEN's param_daemon refuses too ("You must specify a
    robot name on the command line using --robot"), listing them here.

    :param ini: the file read by :func:`read_ini`.
    :param robot: the robot asked for (``-R``/``--robot``), in any case; ``None``: none asked for.
    :raises ConfigError: for an unknown robot, or several robots and none chosen.
    """
    if robot is not None:
        return ini.robot(robot)
    names = ini.robots()
    if len(names) > 1:
        raise ConfigError(ini.path, None, f'{len(names)} robots ({", ".join(names)}): choose one '
                                          'with -R ROBOT or --robot=ROBOT')
    return names[0] if names else None
