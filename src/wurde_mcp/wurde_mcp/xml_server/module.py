"""``xml_server``: Pluto's xmlServer as a WURDE module — the robot's streams as Mobotware variables
on a TCP socket (Pluto 2; AU Robot Servers, "Interface description").

    ros2 run wurde_mcp xml_server [-p PORT] [-b ADDRESS] [-d DIR] [-B BASE] [-L LASER] [-G GPS]

One thread: each turn of the guide's loop takes in what arrived on the streams
(:class:`~.robot_table.RobotPool`) and serves the sockets for up to :data:`SERVE_S` (the turn
returns as soon as a client needs nothing more), so a reply is never older than one turn.
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager
from wurde_core.module_loop import run_loop, set_loop

from .robot_table import DEVICE_DEFAULTS, RobotPool
from .server import ServerSettings, XmlServer

__all__ = ['SERVE_S', 'main']

#: Longest wait for socket activity per loop turn (s): streams are taken in at least this often.
SERVE_S = 0.01

VERSION = '1.0'

HELP = ('  -p PORT     TCP port, 24919..24930 as Mobotware servers, 0 any free one (default 24919)\n'
        '  -b ADDRESS  address to bind (default 127.0.0.1: this host only)\n'
        '  -d DIR      directory of the var logfile xmlServer.var.log (default .)\n'
        f'  -B NAME     the base module (default {DEVICE_DEFAULTS["base"]})\n'
        f'  -L NAME     the laser module (default {DEVICE_DEFAULTS["laser"]})\n'
        f'  -G NAME     the GPS module (default {DEVICE_DEFAULTS["gps"]})')


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('xmlServer')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'p:b:d:B:L:G:').user
    try:
        settings = ServerSettings(name='xmlServer', version=VERSION, host=opts.get('b', '127.0.0.1'),
                                  port=int(opts.get('p', 24919)), data_path=opts.get('d', '.'))
    except ValueError as exc:
        print(f'xml_server: {exc}', file=sys.stderr, flush=True)
        return 2
    devices = {key: opts[letter] for key, letter in (('base', 'B'), ('laser', 'L'), ('gps', 'G'))
               if letter in opts}
    robot = RobotPool(manager, devices)
    server = XmlServer(robot.pool, settings)
    try:
        server.start()
    except OSError as exc:
        print(f'xml_server: cannot listen on {settings.host}:{settings.port}: {exc}', file=sys.stderr, flush=True)
        manager.clean_up()
        return 1
    print(f'xml_server listening on {settings.host}:{server.port}', flush=True)
    set_loop(manager, 0.0)

    def step() -> None:
        robot.refresh()
        server.serve(SERVE_S)

    return run_loop(manager, step, server.close)


if __name__ == '__main__':
    sys.exit(main())
