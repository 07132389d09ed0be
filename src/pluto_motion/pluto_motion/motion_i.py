"""motion_i: Pluto's keyboard program for the motionModule (Pluto 5, 6.3).

The keys common to every link (:mod:`pluto_motion.key_program`; the arrows' velocity commands pass
through to the avoidModule and stop a running motion) and the motionModule's own: ``m`` moveto
(asks for x y), ``i`` investigate, ``e`` explore (asks for the rectangle's b h), ``c`` resume
(cmdFlags 45), ``x`` set the rectangle (asks for b h x y theta; b = 0 removes it).
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager

from .key_program import KeyProgram, run_program
from .motion_proxy import MotionProxy

__all__ = ['MotionKeys', 'main']

#: element[2] and element[3] of motion/status (Pluto 6.3; 3 and 4 of element[2] are ours).
MOVETO_CODES = {-1: 'moveto set', -2: 'nearing', 1: 'at goal', 2: 'investigate done', 3: 'unreachable',
                4: 'blocked, waiting', 0: '-'}
MOTION_CODES = {-10: 'thread stopped', -1: 'idle, rectangle set', 0: 'idle', 1: 'scanning', 3: 'following',
                11: 'approaching', 12: 'circling'}


class MotionKeys(KeyProgram):
    """The motionModule's keys."""

    KEYS = 'm moveto x y, i investigate, e explore b h, c resume, x rectangle b h x y theta'

    def velocity(self, tv: float, rv: float) -> str:
        self.proxy.send(0, [tv, rv])
        return ''

    def key(self, key: str, tv: float, rv: float) -> bool:
        if key == 'm':
            point = self.ask('moveto x y (m, Localization/Pose frame)', 2)
            if point is not None:
                self.proxy.moveto(*point)
                self.say(f'moveto {point[0]:.2f} {point[1]:.2f}')
        elif key == 'i':
            self.proxy.investigate()
            self.say('investigate')
        elif key == 'e':
            size = self.ask('explore: rectangle b h (m)', 2)
            if size is not None:
                self.proxy.explore(*size)
                self.say(f'explore {size[0]:.1f} x {size[1]:.1f}')
        elif key == 'c':
            self.proxy.resume()
            self.say('resume')
        elif key == 'x':
            values = self.ask('rectangle b h x y theta', 5)
            if values is not None:
                self.proxy.set_rectangle(*values)
                self.say('rectangle ' + ' '.join(f'{v:.2f}' for v in values))
        else:
            return False
        return True

    def describe(self) -> str:
        e2, e3 = self.proxy.moveto_status, self.proxy.motion_status
        if e2 is None or e3 is None:
            return ''
        return f' moveto {e2} ({MOVETO_CODES.get(e2, "?")}) motion {e3} ({MOTION_CODES.get(e3, "?")})'


def main(argv: list[str] | None = None) -> int:
    def make(manager: CommsManager, user: dict[str, str], ask) -> KeyProgram:
        return MotionKeys(MotionProxy(manager), ask)

    return run_program('motion_i', '', '', make, argv)


if __name__ == '__main__':
    sys.exit(main())
