"""sick_i: the keyboard program of the laser (Pluto 5, 8.1), through :class:`.sick_proxy.SickProxy`.

The laser takes no commands (8.1); ``s`` prints the newest scan (points, range straight ahead,
nearest range and bearing), ``r`` the RWI copy's.  The status line shows the timing interface's
number of points, or the fatal error ("all data is set to -1").
"""

from __future__ import annotations

import math
import sys


from .key_program import Keys, run_program
from .sick_proxy import Scan, SickProxy

__all__ = ['SickKeys', 'main']

HELP = '  -s LASER     the laser module (default PlutoLaser)'


def describe(name: str, scan: Scan | None) -> str:
    if scan is None:
        return f'{name}: none yet'
    if scan.fatal:
        return f'{name} {len(scan.ranges)} points: fatal error (all -1)'
    near, bearing = scan.nearest()
    return (f'{name} {len(scan.ranges)} points ahead {scan.ahead():.2f} m nearest {near:.2f} m '
            f'at {math.degrees(bearing):+.1f} deg')


class SickKeys(Keys):
    KEYS = 's scan, r RWI scan'

    def act(self, key: str) -> bool:
        if key == 's':
            self.say(describe('scan', self.proxy.scan))
        elif key == 'r':
            self.say(describe('rwi', self.proxy.rwi))
        else:
            return False
        return True

    def status(self) -> str:
        laser: SickProxy = self.proxy
        if laser.scan is not None and laser.scan.fatal:
            return 'laser fatal error: rebooting'
        return f'laser {laser.points} points' if laser.points is not None else ''


def main(argv: list[str] | None = None) -> int:
    return run_program('sick_i', 's:', HELP,
                       lambda manager, user, ask: SickKeys(SickProxy(manager, user.get('s', 'PlutoLaser')), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
