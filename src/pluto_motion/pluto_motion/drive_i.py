"""drive_i: Pluto's keyboard program for the driveModule (Pluto 5, 6.1).

The keys common to every link (:mod:`pluto_motion.key_program`: arrows from the working command,
space, ``a``, ``r``, ``q``) and the drive's own: ``s`` sonar protection on/off (cmdFlags +10), ``h``
hold the current heading at the current speed (the regulator, cmdFlags 1/11).
"""

from __future__ import annotations

import math
import sys

from wurde_core import CommsManager

from .drive_proxy import DriveProxy
from .heading_source import HeadingSource
from .key_program import KeyProgram, run_program

__all__ = ['DriveKeys', 'main']

HELP = '  -b BASE      the base (PlutoBase): the heading source of "h" falls back to its odometry'


class DriveKeys(KeyProgram):
    """The driveModule's keys."""

    KEYS = 's sonar on/off, h hold heading'

    def __init__(self, drive: DriveProxy, heading: HeadingSource, ask, out=sys.stdout) -> None:
        super().__init__(drive, ask, out)
        self.heading = heading
        self.sonar = False

    def velocity(self, tv: float, rv: float) -> str:
        self.proxy.velocity(tv, rv, sonar=self.sonar)
        return ' sonar' if self.sonar else ''

    def key(self, key: str, tv: float, rv: float) -> bool:
        if key == 's':
            self.sonar = not self.sonar
            self.proxy.velocity(tv, rv, sonar=self.sonar)
            self.say(f'sonar protection {"on" if self.sonar else "off"}')
        elif key == 'h':
            theta = self.heading.heading()
            if theta is None:
                self.say('no heading known: not holding one')
            else:
                self.proxy.heading(tv, theta, sonar=self.sonar)
                self.say(f'holding heading {math.degrees(theta):.1f} deg at {tv:+.2f} m/s')
        else:
            return False
        return True

    def show_status(self) -> None:
        self.heading.update()
        super().show_status()


def main(argv: list[str] | None = None) -> int:
    def make(manager: CommsManager, user: dict[str, str], ask) -> KeyProgram:
        heading = HeadingSource(manager, user.get('b', 'PlutoBase'), manager.log_warning)
        return DriveKeys(DriveProxy(manager), heading, ask)

    return run_program('drive_i', 'b:', HELP, make, argv)


if __name__ == '__main__':
    sys.exit(main())
