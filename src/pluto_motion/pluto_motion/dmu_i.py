"""dmu_i: the keyboard program of the DMU (Pluto 5, 8.2), through :class:`.dmu_proxy.DmuProxy`.

The sensor takes no commands; ``d`` prints the filtered DMUstate (heading, pitch, roll, rates,
accelerations), ``r`` the raw one.  The status line shows heading, pitch and roll in degrees.
"""

from __future__ import annotations

import math
import sys


from .dmu_proxy import DmuProxy, Inertial
from .key_program import Keys, run_program

__all__ = ['DmuKeys', 'main']

HELP = '  -d DMU       the DMU module (default PlutoDMU)'


def describe(name: str, state: Inertial | None) -> str:
    if state is None:
        return f'{name}: none yet'
    rates = ' '.join(f'{r:+.3f}' for r in state.rates)
    accels = ' '.join(f'{a:+.2f}' for a in state.accelerations)
    return (f'{name} theta {state.theta:+.4f} phi {state.phi:+.4f} psi {state.psi:+.4f} rad '
            f'rates {rates} rad/s accelerations {accels} m/s2')


class DmuKeys(Keys):
    KEYS = 'd filtered state, r raw state'

    def act(self, key: str) -> bool:
        if key == 'd':
            self.say(describe('dmu', self.proxy.state))
        elif key == 'r':
            self.say(describe('raw', self.proxy.raw))
        else:
            return False
        return True

    def status(self) -> str:
        s = self.proxy.state
        if s is None:
            return ''
        return (f'dmu heading {math.degrees(s.theta):+.0f} pitch {math.degrees(s.phi):+.0f} '
                f'roll {math.degrees(s.psi):+.0f} deg')


def main(argv: list[str] | None = None) -> int:
    return run_program('dmu_i', 'd:', HELP,
                       lambda manager, user, ask: DmuKeys(DmuProxy(manager, user.get('d', 'PlutoDMU')), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
