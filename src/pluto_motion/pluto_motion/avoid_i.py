"""avoid_i: Pluto's keyboard program for the avoidModule (Pluto 5, 6.2).

The keys common to every link (:mod:`pluto_motion.key_program`) and the avoidModule's own: ``s`` and
``l`` sonar and laser protection on/off for the velocity commands (A of cmdFlags = 10·A + T), ``g``
goto a point (asks for x y in the Localization/Pose frame; cmdFlags 32, laser and sonar avoidance),
``w`` wall follow at the current speed (asks for the distance to keep).
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager

from .avoid_proxy import AvoidProxy
from .key_program import KeyProgram, run_program

__all__ = ['AvoidKeys', 'main']

GOTO_TV, GOTO_RV = 0.5, 1.0
#: element[1] of avoidance/status (Pluto 6.2).
GOTO_CODES = {1: 'reached', 2: 'stuck', -1: 'going', -10: 'thread stopped', 0: 'no goto'}


class AvoidKeys(KeyProgram):
    """The avoidModule's keys."""

    KEYS = 's sonar on/off, l laser on/off, g goto x y, w wall follow'

    def __init__(self, avoid: AvoidProxy, ask, out=sys.stdout) -> None:
        super().__init__(avoid, ask, out)
        self.sonar = self.laser = False

    def velocity(self, tv: float, rv: float) -> str:
        self.proxy.velocity(tv, rv, sonar=self.sonar, laser=self.laser)
        return (' sonar' if self.sonar else '') + (' laser' if self.laser else '')

    def key(self, key: str, tv: float, rv: float) -> bool:
        if key in ('s', 'l'):
            if key == 's':
                self.sonar = not self.sonar
            else:
                self.laser = not self.laser
            self.velocity(tv, rv)
            self.say(f'sonar {"on" if self.sonar else "off"}, laser {"on" if self.laser else "off"}')
        elif key == 'g':
            point = self.ask('goto x y (m, Localization/Pose frame)', 2)
            if point is not None:
                self.proxy.goto(point[0], point[1], GOTO_TV, GOTO_RV)
                self.say(f'goto {point[0]:.2f} {point[1]:.2f}')
        elif key == 'w':
            distance = self.ask('wall follow: distance to keep (m, 0 for the default)', 1)
            if distance is not None:
                self.proxy.wall_follow(max(tv, 0.2), distance[0])
                self.say(f'wall follow at {max(tv, 0.2):.2f} m/s')
        else:
            return False
        return True

    def describe(self) -> str:
        goto = self.proxy.goto_status
        return '' if goto is None else f' goto {goto} ({GOTO_CODES.get(goto, "?")})'


def main(argv: list[str] | None = None) -> int:
    def make(manager: CommsManager, user: dict[str, str], ask) -> KeyProgram:
        return AvoidKeys(AvoidProxy(manager), ask)

    return run_program('avoid_i', '', '', make, argv)


if __name__ == '__main__':
    sys.exit(main())
