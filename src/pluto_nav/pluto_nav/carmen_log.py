"""``carmen_log``: a CARMEN log played onto the robot's streams, or converted to a ROS 2 bag.

    carmen_log play LOG [-R RATE] [-b BASE] [-s LASER] [-L CHANNEL] [-w SECONDS] [-k] [-t] [-n NAME]
    carmen_log convert LOG OUT.mcap

``play`` (:mod:`.carmen_log_play`) is a WURDE module supplying what the simulated robot's base and
laser dummies supply (``<BASE>Motion``, ``<LASER>``, ``<LASER>/Timing`` and their standard ROS
mirrors), from the log, so that the localModule, poseModule and slamModule run on a real robot's
recording as on the robot.  ``convert`` (:mod:`.carmen_log_convert`) writes the log as an MCAP
file as rosbag2 writes one, with standard topics only (``/scan``, ``/odom``, ``/tf``,
``/tf_static``, ``/truth``), which rosbag2's tools and wurde_mcp's ``replay`` read.

The log is read by :mod:`pluto_nav.logs.carmen` (plain or gzip); its problems are warned once per
kind with ``file:line`` and counted in the summary.  Exit status: 0 done, 1 the work failed
(e.g. the output cannot be written), 2 wrong arguments or a log that cannot be read at all.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

__all__ = ['main']

USAGE = __doc__.split('\n\n')[1].strip('\n') if __doc__ else ''


def _help() -> str:
    return (f'usage:\n{USAGE}\n\n'
            '  play     publish the log on the WURDE streams at its pace (carmen_log play -h)\n'
            '  convert  write the log as a ROS 2 MCAP bag with standard topics (carmen_log convert -h)\n')


def main(argv: Sequence[str] | None = None) -> int:
    """Dispatch to ``play`` or ``convert``; ``argv`` includes the program name."""
    argv = list(sys.argv if argv is None else argv)
    program = os.path.basename(argv[0]) if argv else 'carmen_log'
    if len(argv) < 2 or argv[1] in ('-h', '--help'):
        print(_help(), end='')
        return 0 if len(argv) >= 2 else 2
    command, rest = argv[1], argv[2:]
    if command == 'play':
        from .carmen_log_play import main as play
        return play([f'{program} play', *rest])
    if command == 'convert':
        from .carmen_log_convert import main as convert
        return convert([f'{program} convert', *rest])
    print(f'{program}: unknown command {command!r} (play or convert)\n{_help()}', end='', file=sys.stderr)
    return 2


if __name__ == '__main__':
    sys.exit(main())
