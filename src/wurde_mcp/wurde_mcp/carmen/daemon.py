"""``param_daemon``: CARMEN's parameter server as a WURDE module whose node serves carmen.ini.

    ros2 run wurde_mcp param_daemon [-a] [-R ROBOT | --robot=ROBOT] [-M RES] [-s STREAM] [MAP] [INI]

Every parameter of the chosen robot (``[*]``, ``[expert]`` and ``[ROBOT]``, read by CARMEN's
rules: :mod:`.ini`) becomes the ROS 2 parameter ``module.variable`` of the node
``/param_daemon``, typed from its text (int, float, on/off as bool, else string), so ``ros2 param``
and ``/parameter_events`` work and the client API (:mod:`wurde_core.carmen_param`, Programming
with CARMEN 6) reads them.  A MAP is served as :mod:`map_server <wurde_mcp.carmen.map_server>`
serves it, as CARMEN's daemon serves its map.  docs/carmen.md ("CARMEN's parameters") is the manual;
docs/wurde-mcp.md ("param_daemon") has the detail of sets, re-reads and where this daemon
differs from CARMEN's.

Before changing it: CARMEN's ``-r ROBOT`` is ``-R`` here because ``-r`` is every WURDE module's
registration mode.  A re-read (the parameter ``reread`` set true) is checked inside rclpy's set
callback, so a refused file refuses the set and the old values stay, and is applied by the
module's loop after that set returns, never from within the callback.  A parameter keeps the type
it was first served with.
"""

from __future__ import annotations

import sys
from typing import Any

from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.parameter import Parameter
from wurde_core import CommsManager
from wurde_core.carmen_param import REREAD, typed_value
from wurde_core.module_loop import exit_on_config_error, run_loop, set_loop
from wurde_core.options import split_ros_arguments
from wurde_idl.errors import ConfigError
from wurde_idl.maps import load_any_map

from .ini import Entry, IniFile, IniWarning, choose_robot, find_ini, read_ini
from .map_server import DEFAULT_RESOLUTION, MapServerModule, from_grid_map, rasterize

__all__ = ['MAP_PARAMETER', 'ParamDaemon', 'carmen_options', 'main', 'ros_name', 'split_arguments']

#: The read-only parameter naming the map file given on the command line.
MAP_PARAMETER = 'map.file'
#: Longest wait per loop turn for a parameter request (s); requests wake the loop at once.
SERVE_S = 0.1

HELP = ('  -a          print the loaded parameters (module_variable value, sorted) at start\n'
        '  -R ROBOT    serve [*], [expert] and [ROBOT] of the ini file (any case; CARMEN\'s -r:\n'
        '              -r is WURDE\'s registration mode; --robot=ROBOT as CARMEN\'s);\n'
        '              needed when the file has several robots\n'
        '  MAP         a map file: the read-only parameter map.file, and the map served as\n'
        '              map_server serves it (MapServer stream and /map)\n'
        '  -M RES      m per cell of the served map\'s grid (default 0.05)\n'
        '  -s STREAM   the MapServer stream of the served map (default MapServer)\n'
        '  INI         the carmen.ini (an argument ending in .ini); default: the first of\n'
        '              ./carmen.ini, ../carmen.ini, ../src/carmen.ini\n'
        '  set the parameter "reread" to true (param_tool reread) to re-read the ini file')


def ros_name(entry: Entry) -> str:
    """``module.variable``: dots, so that ``ros2 param list`` groups a module's parameters.

    :param entry: a carmen.ini line.
    """
    return f'{entry.module}.{entry.variable}'


def split_arguments(arguments: list[str]) -> tuple[str | None, str | None]:
    """``(map, ini)`` from the positional arguments (``[MAP] [INI]``; a lone ``*.ini`` is the ini).

    :param arguments: the positional arguments, in order; of two, the first is the map.
    :returns: the map's and the ini file's paths, None for one not given.
    :raises ValueError: for more than two.
    """
    if len(arguments) > 2:
        raise ValueError(f'at most a map and an ini file, not {" ".join(arguments)}')
    if len(arguments) == 2:
        return arguments[0], arguments[1]
    if arguments and arguments[0].endswith('.ini'):
        return None, arguments[0]
    return (arguments[0] if arguments else None), None


def carmen_options(argv: list[str]) -> list[str]:
    """``argv`` with CARMEN's long option ``--robot=ROBOT`` (or ``--robot ROBOT``) written as
    ``-R ROBOT`` right after the program name, where WURDE's option parser takes it (it knows no
    long options and stops at the first argument).  ROS arguments are left as they are.

    :param argv: the command line, the program's name first.
    :raises ValueError: for ``--robot`` without a robot.
    """
    own, ros = split_ros_arguments(argv[1:])
    robot: list[str] = []
    rest: list[str] = []
    words = iter(own)
    for word in words:
        if word == '--robot' or word.startswith('--robot='):
            name = word.partition('=')[2] if '=' in word else next(words, '')
            if not name:
                raise ValueError('--robot needs a robot name (--robot=ROBOT)')
            robot = ['-R', name]
        else:
            rest.append(word)
    return [*argv[:1], *robot, *rest, *ros]


def _kind(value: Any) -> str:
    return {bool: 'on/off', int: 'int', float: 'double', str: 'string'}[type(value)]


class ParamDaemon:
    """The parameters of one robot of one carmen.ini on ``node``."""

    def __init__(self, node: Any, ini: IniFile, robot: str | None, map_path: str | None) -> None:
        """Take the parameters to serve; :meth:`declare` declares them.

        :param node: the rclpy node whose parameters they become.
        :param ini: the carmen.ini read; re-reads read its path again.
        :param robot: the robot chosen (:func:`~.ini.choose_robot`), None for ``[*]`` and
            ``[expert]`` only.
        :param map_path: the map file given on the command line, None for none; when given, the
            file's own ``map_file`` parameter is not served (the read-only ``map.file`` is).
        """
        self.node = node
        self.path = ini.path
        self.robot = robot
        self.map_path = map_path
        self.entries = self._served(ini)
        self._pending: dict[str, Entry] | None = None
        self._pending_warnings: list[IniWarning] = []
        self._told: set[IniWarning] = set()

    def _served(self, ini: IniFile) -> dict[str, Entry]:
        entries = ini.parameters(self.robot)
        if self.map_path is not None:   # the command line's map wins over the file's map_file
            entries = {name: entry for name, entry in entries.items() if name.lower() != 'map_file'}
        return entries

    def warn(self, warnings: list[IniWarning]) -> int:
        """Print on stderr each of ``warnings`` not printed before; returns how many were.

        :param warnings: the reader's warnings (of the first read or a re-read).
        """
        new = [warning for warning in warnings if warning not in self._told]
        for warning in new:
            print(f'param_daemon: warning: {warning}', file=sys.stderr, flush=True)
        self._told.update(new)
        return len(new)

    def declare(self) -> None:
        """Declare every parameter, the map and the ``reread`` trigger."""
        self.node.add_pre_set_parameters_callback(self._widen)
        self.node.add_on_set_parameters_callback(self._check)
        for entry in self.entries.values():
            self._declare(entry)
        if self.map_path is not None:
            self.node.declare_parameter(MAP_PARAMETER, self.map_path, ParameterDescriptor(
                description='the map file given to param_daemon', read_only=True))
        self.node.declare_parameter(REREAD, False, ParameterDescriptor(
            description=f'set true to re-read {self.path}'))

    def _declare(self, entry: Entry) -> None:
        self.node.declare_parameter(ros_name(entry), typed_value(entry.value), ParameterDescriptor(
            description=f'carmen.ini {entry.name}' + (' (expert)' if entry.expert else '')))

    def listing(self) -> list[str]:
        """``module_variable value`` of every served parameter, sorted (``-a``)."""
        lines = {name: f'{name} {entry.value}' for name, entry in self.entries.items()}
        if self.map_path is not None:
            lines['map_file'] = f'map_file {self.map_path}'
        return [lines[name] for name in sorted(lines)]

    def _widen(self, parameters: list[Parameter]) -> list[Parameter]:
        """An int set on a double parameter is taken as that double."""
        return [Parameter(p.name, value=float(p.value))
                if p.type_ == Parameter.Type.INTEGER and self._type(p.name) == Parameter.Type.DOUBLE
                else p for p in parameters]

    def _type(self, name: str) -> Parameter.Type | None:
        return self.node.get_parameter(name).type_ if self.node.has_parameter(name) else None

    def _check(self, parameters: list[Parameter]) -> SetParametersResult:
        """A set of ``reread`` to true reads the file now: refused with file:line: reason when
        the file is; else the loop applies it after this set returns."""
        for parameter in parameters:
            if parameter.name == REREAD and parameter.value is True:
                try:
                    self._pending = self.prepare()
                except ConfigError as error:
                    return SetParametersResult(successful=False, reason=str(error))
        return SetParametersResult(successful=True)

    def prepare(self) -> dict[str, Entry]:
        """The ini file's parameters for this robot, read again.

        :raises ConfigError: for a file that cannot be read or is not UTF-8, a robot no longer in
            it, or a value whose type differs from the one served (an int for a double is fine).
        """
        ini = read_ini(self.path)
        entries = self._served(ini)
        for entry in entries.values():
            served = self._type(ros_name(entry))
            value = Parameter(ros_name(entry), value=typed_value(entry.value))
            if served is None or served == value.type_ or (
                    served == Parameter.Type.DOUBLE and value.type_ == Parameter.Type.INTEGER):
                continue
            old = self.node.get_parameter(ros_name(entry)).value
            raise ConfigError(entry.path, entry.line,
                              f'{entry.name} {entry.value!r} is {_kind(value.value)}, but it is '
                              f'served as {_kind(old)}: restart param_daemon to change a type')
        self._pending_warnings = ini.warnings
        return entries

    def apply_pending(self) -> int:
        """Set what a re-read found changed, declare what is new; returns how many changed."""
        entries, self._pending = self._pending, None
        if entries is None:
            return 0
        self.warn(self._pending_warnings)
        changed = []
        for entry in entries.values():
            name, value = ros_name(entry), typed_value(entry.value)
            if not self.node.has_parameter(name):
                self._declare(entry)
                changed.append(name)
            elif self.node.get_parameter(name).value != value:
                result = self.node.set_parameters([Parameter(name, value=value)])[0]
                if result.successful:
                    changed.append(name)
                else:
                    print(f'param_daemon: {entry.path}:{entry.line}: {result.reason}',
                          file=sys.stderr, flush=True)
        self.entries.update(entries)
        self.node.set_parameters([Parameter(REREAD, value=False)])
        print(f'param_daemon reread {self.path}: {len(changed)} changed'
              + (f' ({", ".join(changed)})' if changed else ''), flush=True)
        return len(changed)


def main(argv: list[str] | None = None) -> int:
    """Run ``param_daemon`` until it is told to quit.

    :param argv: the command line, the program's name first (None: ``sys.argv``).
    :returns: the exit status (2 for a usage error, a refused file or map).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('param_daemon')
    manager.set_help_string(HELP)
    try:
        argv = carmen_options(argv)
    except ValueError as error:
        print(f'param_daemon: {error}', file=sys.stderr, flush=True)
        return 2
    opts = manager.parse_options(argv, 'aR:M:s:')
    try:
        map_path, ini_path = split_arguments(opts.arguments)
    except ValueError as error:
        print(f'param_daemon: {error}', file=sys.stderr, flush=True)
        return 2
    try:
        ini = read_ini(ini_path or find_ini())
        robot = choose_robot(ini, opts.user.get('R'))
        loaded = load_any_map(map_path) if map_path else None      # XML, map_server YAML or CARMEN map
        world = loaded.data if loaded else None
        if loaded is None:
            grid = None
        elif loaded.grid is not None:
            grid = from_grid_map(loaded.grid)                        # a grid map's own cells
        else:
            grid = rasterize(loaded.data, float(opts.user.get('M', DEFAULT_RESOLUTION)))
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    except ValueError as error:
        print(f'param_daemon: -M: {error}', file=sys.stderr, flush=True)
        return 2
    manager.wait(0.0)   # opens the module's node
    daemon = ParamDaemon(manager.node, ini, robot, map_path)
    daemon.warn(ini.warnings)
    daemon.declare()
    maps = None
    if world is not None and grid is not None:
        maps = MapServerModule(manager, world, grid, opts.user.get('s', 'MapServer'))
        print(f'param_daemon serves the map {world.name} ({grid.width} x {grid.height} cells of '
              f'{grid.resolution} m) on {maps.obj.stream} and /map', flush=True)
    if 'a' in opts.user:
        print('\n'.join(daemon.listing()), flush=True)
    print(f'param_daemon serves {len(daemon.entries)} parameters of '
          f'{"[" + robot + "]" if robot else "[*]"} from {ini.path}', flush=True)
    print('param_daemon ready', flush=True)
    set_loop(manager, 0.0)

    def step() -> None:
        daemon.apply_pending()
        if maps is not None:
            maps.step()
        manager.wait(SERVE_S)

    return run_loop(manager, step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
