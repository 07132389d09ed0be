"""base_i: the keyboard program of the base (Pluto 5: "each module has a simple user interface that
allows control from the keyboard"), through :class:`.base_proxy.BaseProxy`.

Arrow keys change the velocities (0.1 m/s, 0.1 rad/s) from the ones the base executes now (its
command data; before the base has published one, the odometry's), space
stops, ``k`` asks for the odometry calibration (distance and rotation scales) and sets it.  Nothing
is repeated: the base's watchdog stops a robot whose keyboard went quiet.  The status line shows
the odometry, velocities, calibration, bumpers, nearest sonar and battery.
"""

from __future__ import annotations

import sys


from pluto_nav.odometry_calibration import Calibration

from .base_proxy import BaseProxy
from .key_program import Keys, run_program, step_velocity

__all__ = ['BaseKeys', 'main']

HELP = '  -b BASE      the base module (default PlutoBase)'


class BaseKeys(Keys):
    KEYS = 'arrows drive, space stops, k calibration'

    def act(self, key: str) -> bool:
        base: BaseProxy = self.proxy
        if key in ('up', 'down', 'left', 'right'):
            tv, rv = step_velocity(key, *(base.velocities or base.speeds or (0.0, 0.0)))
            base.velocity(tv, rv)
            self.say(f'command tv {tv:+.2f} m/s rv {rv:+.2f} rad/s')
        elif key == 'space':
            base.stop()
            self.say('command stop')
        elif key == 'k':
            scales = self.ask('distance and rotation scales', 2)
            if scales is not None:
                base.calibrate(Calibration(*scales))
                self.say(f'calibration {scales[0]:.4f} {scales[1]:.4f} sent')
        else:
            return False
        return True

    def quit(self) -> None:
        self.proxy.stop()

    def status(self) -> str:
        base: BaseProxy = self.proxy
        if base.pose is None:
            return ''
        x, y, theta = base.pose
        tv, rv = base.velocities or base.speeds or (0.0, 0.0)
        c = base.calibration
        calibration = f'{c.distance:.4f} {c.rotation:.4f}' if c is not None else '?'
        bumpers = ''.join('1' if b else '0' for b in base.bumpers)
        sonar = f' sonar {min(base.ranges):.2f}' if base.ranges else ''
        battery = f' battery {base.voltage:.1f} V' if base.voltage is not None else ''
        return (f'base x {x:+.2f} y {y:+.2f} theta {theta:+.2f} tv {tv:+.2f} rv {rv:+.2f} '
                f'calibration {calibration} bumpers {bumpers or "-"}{sonar}{battery}')

    def close(self) -> None:
        self.proxy.command.wait_delivered(1.0)


def main(argv: list[str] | None = None) -> int:
    return run_program('base_i', 'b:', HELP,
                       lambda manager, user, ask: BaseKeys(BaseProxy(manager, user.get('b', 'PlutoBase')), ask), argv)


if __name__ == '__main__':
    sys.exit(main())
