"""wrist_i: the keyboard program of the wrist (Pluto 5, 8.3), through :class:`.wrist_proxy.WristProxy`.

Left/right turn the pan by 0.1 rad, up/down the tilt, from the command being executed; ``c``
centres, ``h`` halts, ``p`` asks for a pan and a tilt.  The status line shows the state and the
target.
"""

from __future__ import annotations

import sys


from .key_program import Keys, run_program
from .wrist_proxy import WristProxy

__all__ = ['WristKeys', 'main']

HELP = '  -w WRIST     the wrist module (default PlutoWrist)'
STEP = 0.1


class WristKeys(Keys):
    KEYS = 'left/right pan, up/down tilt, c centre, h halt, p pan tilt'

    def _move(self, pan: float, tilt: float) -> None:
        self.proxy.move(pan, tilt)
        self.say(f'wrist command pan {pan:+.2f} tilt {tilt:+.2f}')

    def act(self, key: str) -> bool:
        wrist: WristProxy = self.proxy
        pan, tilt = wrist.target or wrist.position or (0.0, 0.0)
        if key in ('left', 'right', 'up', 'down'):
            pan += {'left': STEP, 'right': -STEP}.get(key, 0.0)
            tilt += {'up': STEP, 'down': -STEP}.get(key, 0.0)
            self._move(round(pan, 3), round(tilt, 3))
        elif key == 'c':
            self._move(0.0, 0.0)
        elif key == 'h':
            wrist.halt()
            self.say('wrist halt')
        elif key == 'p':
            values = self.ask('pan tilt (rad)', 2)
            if values is not None:
                self._move(*values)
        else:
            return False
        return True

    def status(self) -> str:
        wrist: WristProxy = self.proxy
        if wrist.position is None:
            return ''
        target = f' target {wrist.target[0]:+.2f} {wrist.target[1]:+.2f}' if wrist.target else ''
        return f'wrist pan {wrist.position[0]:+.2f} tilt {wrist.position[1]:+.2f}{target}'

    def close(self) -> None:
        self.proxy.wrist.wait_delivered(1.0)


def main(argv: list[str] | None = None) -> int:
    return run_program('wrist_i', 'w:', HELP,
                       lambda manager, user, ask: WristKeys(WristProxy(manager, user.get('w', 'PlutoWrist')), ask),
                       argv)


if __name__ == '__main__':
    sys.exit(main())
