"""local_i: the keyboard program of the localModule (Pluto 3, 5), through :class:`.local_proxy.LocalProxy`.

``p`` prints the five pose interfaces, numbered from 0 "as the loc_proxy numbers its interfaces";
``e`` asks for x, y, theta and sets that robot pose (setter -1; Pluto 7.1: a pose thread running
must be stopped first, or the localModule refuses it).  The status line shows whether odometry and
DMU are fresh, the setter and the refused writes.
"""

from __future__ import annotations

import sys

from pluto_nav.streams import STREAMS, USER_SETTER

from .key_program import Keys, run_program
from .local_proxy import LocalProxy

__all__ = ['LocalKeys', 'main']


class LocalKeys(Keys):
    KEYS = 'p poses, e set pose'

    def act(self, key: str) -> bool:
        local: LocalProxy = self.proxy
        if key == 'p':
            for n, name in enumerate(STREAMS):
                p = local.get_pose(n)
                self.say(f'{n} {name}: none yet' if p is None else
                         f'{n} {name} x {p.pose[0]:+.3f} y {p.pose[1]:+.3f} theta {p.pose[3]:+.4f} setter {p.setter}')
        elif key == 'e':
            values = self.ask('x y theta', 3)
            if values is not None:
                local.set_pose((values[0], values[1], values[2]), USER_SETTER)
                self.say(f'set pose {values[0]:+.3f} {values[1]:+.3f} {values[2]:+.4f}')
        else:
            return False
        return True

    def status(self) -> str:
        local: LocalProxy = self.proxy
        if local.odometry_fresh is None:
            return ''
        return (f'local odometry {int(local.odometry_fresh)} dmu {int(bool(local.dmu_fresh))} '
                f'setter {local.setter} refused {local.refused}')


def main(argv: list[str] | None = None) -> int:
    return run_program('local_i', '', '', lambda manager, user, ask: LocalKeys(LocalProxy(manager), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
