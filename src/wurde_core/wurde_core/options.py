"""Command-line options common to every module (guide 5.1.1 and chapter 7).

``-r`` registration mode, ``-o`` namespace override, ``-n NAME`` module name override, ``-g FILE``
role-config file, ``-l`` list capabilities, ``-h`` help; user options in getopt form (``"c:ab"``)
land in the global configuration (``get_option("c")``).  ROS arguments (``--ros-args ...``) are
passed through to rclpy untouched.
"""

from __future__ import annotations

import getopt
from dataclasses import dataclass, field

from .errors import OptionError

STANDARD_SPEC = 'rog:n:lh'


@dataclass
class Options:
    """What parse_options found."""

    registration: bool = False
    namespace_override: bool = False
    name: str | None = None
    config_file: str | None = None
    list_capabilities: bool = False
    help: bool = False
    user: dict[str, str] = field(default_factory=dict)
    arguments: list[str] = field(default_factory=list)
    ros_arguments: list[str] = field(default_factory=list)


def split_ros_arguments(argv: list[str]) -> tuple[list[str], list[str]]:
    """``(own arguments, ROS arguments)``: everything from ``--ros-args`` to ``--`` is ROS's.

    :param argv: the arguments, without the program name.
    """
    own: list[str] = []
    ros: list[str] = []
    inside = False
    for arg in argv:
        if arg == '--ros-args':
            inside = True
            ros.append(arg)
        elif inside and arg == '--':
            inside = False
            ros.append(arg)
        elif inside:
            ros.append(arg)
        else:
            own.append(arg)
    return own, ros


def parse(argv: list[str], user_spec: str | None = None) -> Options:
    """Parse the standard options and the user's.

    :param argv: the arguments, without the program name.
    :param user_spec: the user options in getopt form (``"c:ab"``); None: none.  An option
        without a value reads ``"true"``.
    :raises OptionError: for an unknown option, a missing argument, or a user option that
        clashes with a standard one.
    """
    spec = user_spec or ''
    for letter in spec.replace(':', ''):
        if letter in STANDARD_SPEC.replace(':', ''):
            raise OptionError(f'user option -{letter} clashes with a standard option')
    own, ros = split_ros_arguments(argv)
    try:
        pairs, rest = getopt.getopt(own, STANDARD_SPEC + spec)
    except getopt.GetoptError as exc:
        raise OptionError(str(exc)) from exc
    options = Options(arguments=rest, ros_arguments=ros)
    for flag, value in pairs:
        letter = flag[1]
        if letter == 'r':
            options.registration = True
        elif letter == 'o':
            options.namespace_override = True
        elif letter == 'n':
            options.name = value
        elif letter == 'g':
            options.config_file = value
        elif letter == 'l':
            options.list_capabilities = True
        elif letter == 'h':
            options.help = True
        else:
            options.user[letter] = value if value else 'true'
    return options


def usage(program: str, name: str, user_spec: str | None, help_string: str) -> str:
    """The -h text.

    :param program: the program's name, in the usage line.
    :param name: the module's name.
    :param user_spec: the user options in getopt form, listed as given; None: none.
    :param help_string: the program's own text, appended; empty: none.
    """
    lines = [f'usage: {program} [-r] [-o] [-l] [-h] [-n NAME] [-g ROLE_CONFIG]'
             f'{" [user options: " + user_spec + "]" if user_spec else ""} [--ros-args ...]',
             f'WURDE module {name}',
             '  -r  registration mode: report capabilities to the MCP and exit',
             '  -l  list capabilities (print them and send them to the MCP)',
             '  -o  namespace override (accepted; DDS, like CMU IPC, allows duplicate names)',
             '  -n  module name override',
             '  -g  role-config file (default role-config.xml in the working directory)',
             '  -h  this help']
    if help_string:
        lines.append(help_string)
    return '\n'.join(lines)
