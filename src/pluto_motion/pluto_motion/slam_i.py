"""slam_i: the keyboard program of the slamModule (Pluto 5, 7.2), through :class:`.slam_proxy.SlamProxy`.

``a`` starts the slam thread ("The slam thread does not start automatically ... one must start it
when ready"), ``s`` stops it (which saves the map), ``m`` saves the map.  The status line shows
the thread, the save, the walls and landmarks and the maps saved so far.
"""

from __future__ import annotations

import sys

from .key_program import Keys, run_program
from .slam_proxy import SlamProxy

__all__ = ['SlamKeys', 'main']


class SlamKeys(Keys):
    KEYS = 'a start, s stop (saves), m save map'

    def act(self, key: str) -> bool:
        slam: SlamProxy = self.proxy
        if key == 'a':
            slam.start_activity()
            self.say('slam start')
        elif key == 's':
            slam.stop()
            self.say('slam stop')
        elif key == 'm':
            slam.save_map()
            self.say('slam save map')
        else:
            return False
        return True

    def status(self) -> str:
        slam: SlamProxy = self.proxy
        if slam.running is None:
            return ''
        return (f'slam running {slam.running} saving {int(slam.saving)} walls {slam.walls} '
                f'landmarks {slam.landmarks} maps saved {slam.maps_saved}')

    def close(self) -> None:
        self.proxy.status.wait_delivered(1.0)


def main(argv: list[str] | None = None) -> int:
    return run_program('slam_i', '', '', lambda manager, user, ask: SlamKeys(SlamProxy(manager), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
