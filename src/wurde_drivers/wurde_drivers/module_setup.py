"""What every driver and dummy module does the same way: the shared loop helpers of
:mod:`wurde_core.module_loop` (re-exported here) and picking its ``<device>`` from a config file.
Nothing here knows the simulator (real drivers never import it)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from wurde_core import CommsManager
from wurde_core.module_loop import MODULE_TTL_S, config_file, exit_on_config_error, run_loop, set_loop
from wurde_idl.errors import ConfigError

from .xml_config import Device, device_named

__all__ = ['MODULE_TTL_S', 'config_file', 'configured_device', 'exit_on_config_error', 'run_loop',
           'set_loop']


def configured_device(manager: CommsManager, argv: list[str], file_name: str,
                      load: Callable[[str], Sequence[Device]]) -> Device:
    """Parse the options and return the ``<device>`` of the config named like the module.

    Without ``-n``, a config whose one ``<device>`` is not named like the program's default names
    the module after itself: the guide's appendix runs ``rFlexServer`` and ``sickLaser`` with no
    options on its one-device files (10.1.1, 10.1.4, 10.1.5).

    :param manager: the module's manager, its options not parsed yet; ``-n`` picks the device by
        name (WURDE 7.5).
    :param argv: the command line, program name first; ``-c FILE`` names the config.
    :param file_name: the config's default name in the config directory.
    :param load: reads the config file into its devices.
    :raises SystemExit: status 2 with ``file:line: reason`` on stderr for a bad config.
    """
    manager.set_help_string(f'  -c FILE  {file_name} (default: <config dir>/{file_name})\n'
                            '  -n NAME  the module and stream name; picks the <device> by name')
    opts = manager.parse_options(argv, 'c:')
    path = config_file(manager, opts.user.get('c'), file_name)
    try:
        devices = load(path)
        if opts.name is None and len(devices) == 1 and devices[0].name != manager.name:
            manager.parse_options([argv[0], '-n', devices[0].name, *argv[1:]], 'c:')
        return device_named(devices, manager.name, path=path)
    except ConfigError as error:
        raise SystemExit(exit_on_config_error(argv[0], error)) from None
