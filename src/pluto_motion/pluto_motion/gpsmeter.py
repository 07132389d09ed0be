"""gpsmeter: Pluto's GPS program (Pluto 5, 8.4: "use the proxy in gpsmeter to get data into a xy
grid in meter units"), through :class:`.gps_proxy.GpsProxy`.

The status line shows each fix on the grid (m east and north of the origin), the satellites, the
quality and whether the fix is good (8.4: more than 5 satellites, quality 2); ``l`` prints latitude,
longitude, altitude, HDOP and the grid's origin.
"""

from __future__ import annotations

import sys


from .gps_proxy import GpsProxy
from .key_program import Keys, run_program

__all__ = ['GpsKeys', 'main']

HELP = '  -s GPS       the GPS module (default PlutoGPS; -g is WURDE\'s role config option)'

class GpsKeys(Keys):
    KEYS = 'l latitude/longitude'

    def act(self, key: str) -> bool:
        if key != 'l':
            return False
        gps: GpsProxy = self.proxy
        f = gps.fix
        if f is None:
            self.say('gps: no fix yet')
        else:
            origin = f'{gps.origin[0]:.7f} {gps.origin[1]:.7f}' if gps.origin else 'unknown'
            self.say(f'gps latitude {f.latitude:.7f} longitude {f.longitude:.7f} altitude {f.altitude:.1f} m '
                     f'hdop {f.hdop:.1f} origin {origin}')
        return True

    def status(self) -> str:
        gps: GpsProxy = self.proxy
        f = gps.fix
        if f is None:
            return ''
        return (f'gps x {f.x:+.1f} y {f.y:+.1f} m satellites {f.satellites} quality {f.quality} '
                f'{"good" if gps.good else "poor"}')


def main(argv: list[str] | None = None) -> int:
    return run_program('gpsmeter', 's:', HELP,
                       lambda manager, user, ask: GpsKeys(GpsProxy(manager, user.get('s', 'PlutoGPS')), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
