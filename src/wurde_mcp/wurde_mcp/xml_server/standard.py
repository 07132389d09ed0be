"""The commands every xmlServer has beyond ``var``, ``push`` and ``help``: the server core's
``shelp``, ``module``, ``alive``, ``ping`` (:mod:`.core_commands`), the pose commands and their
pushes (:mod:`.pose_hist`) and the laser commands (:mod:`.laser_commands`), grouped as AURS's
``help`` lists them (AU Robot Servers, "Online help").
"""

from __future__ import annotations

from .core_commands import ALIVE_HELP, MODULE_HELP, PING_HELP, ModuleCommand, alive, ping
from .host import ServerHost
from .laser_commands import LASERDATA_HELP, LASEROBST_HELP, LaserData, laser_obstacles
from .pose_hist import POSES, PoseHistCommand, PosePushCommand, pose_help, pose_push_help
from .push_commands import PushCommands

__all__ = ['install_standard']


def install_standard(server: ServerHost, pushes: PushCommands) -> ModuleCommand:
    """Add the commands to ``server``; the ``module`` handler (it owns the loaded interfaces)."""
    modules = ModuleCommand(server)
    add = server.add_command
    add('shelp', server.help_handler, 'The same as help', group='server')
    add('module', modules, 'Module list and addition/removal of modules', help_text=MODULE_HELP,
        group='server')
    add('alive', alive(server), 'Seconds since the last server loop', help_text=ALIVE_HELP,
        group='server')
    add('ping', ping, 'Time difference analysis (ping [tod=sss.usec])', help_text=PING_HELP,
        group='server')
    for source in POSES:
        add(source.alias, PoseHistCommand(server.pool, source), f'The {source.what}',
            help_text=pose_help(source), group=source.alias)
        add(f'{source.alias}Push', PosePushCommand(server.pool, pushes, source),
            f'Push on updates of the {source.what}', help_text=pose_push_help(source),
            group=source.alias)
    modules.load('if', 'laser')                     # AURS's "laser laserOnConnect"
    add('laserdata', LaserData(server.pool), "The newest scan of this server's laser",
        help_text=LASERDATA_HELP, group='laserdata')
    add('laserobst', laser_obstacles, 'Obstacles in the laser scan (none here)',
        help_text=LASEROBST_HELP, group='laserdata')
    return modules
