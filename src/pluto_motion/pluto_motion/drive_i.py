"""drive_i: Pluto's keyboard program for the driveModule (Pluto 5, 6.1).

Arrow keys change the speed: up/down by 0.1 m/s, left/right by 0.1 rad/s.  Each press starts from
the status's data[0..1], the velocities the drive really commands, not from the last command sent:
"By first reading the status the interface knows the working command value of the driveModule"
(6.1) — after a timeout or a bumper stop a press continues from standstill.  The program does not
repeat commands, so the drive's timeout stops a robot whose keyboard has gone quiet, as the seed
intends ("in case the user interface crashes").

Keys: arrows (drive), space (stop), ``s`` sonar protection on/off (cmdFlags +10), ``h`` hold the
current heading at the current speed (the regulator, cmdFlags 1/11), ``a`` start_activity, ``r``
release the robot (cmdFlags -1), ``q`` stop and quit.
"""

from __future__ import annotations

import math
import sys

from wurde_core import CommsManager, Logger, RunState
from wurde_core.module_loop import run_loop, set_loop

from .drive_proxy import DriveProxy
from .heading_source import HeadingSource
from .keyboard import Keyboard

__all__ = ['DriveKeys', 'main']

STEP_TV, STEP_RV = 0.1, 0.1
MAX_TV, MAX_RV = 1.0, 1.5
LOOP_S = 0.05
CODES = {0: 'normal', -1: 'timeout', -10: 'thread stopped', 1: 'front bumper', 2: 'back bumper',
         3: 'sonar front', 4: 'sonar back', 5: 'sonar sides'}
HELP = ('  -b BASE      the base (PlutoBase): the heading source of "h" falls back to its odometry\n'
        'keys: arrows drive, space stops, s sonar on/off, h hold heading, a start, r release, q quit')


def _clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, round(value, 3)))


class DriveKeys:
    """What each key does to the drive."""

    def __init__(self, manager: CommsManager, drive: DriveProxy, heading: HeadingSource, out=sys.stdout) -> None:
        self.manager, self.drive, self.heading, self.out = manager, drive, heading, out
        self.sonar = False
        self.shown = ''

    def _say(self, text: str) -> None:
        print(text, file=self.out, flush=True)

    def press(self, key: str) -> bool:
        """Act on ``key``; False on quit."""
        tv, rv = self.drive.velocities or (0.0, 0.0)          # the working command (Pluto 6.1)
        if key in ('up', 'down', 'left', 'right'):
            tv += {'up': STEP_TV, 'down': -STEP_TV}.get(key, 0.0)
            rv += {'left': STEP_RV, 'right': -STEP_RV}.get(key, 0.0)
            tv, rv = _clamp(tv, MAX_TV), _clamp(rv, MAX_RV)
            self.drive.velocity(tv, rv, sonar=self.sonar)
            self._say(f'command tv {tv:+.2f} m/s rv {rv:+.2f} rad/s{" sonar" if self.sonar else ""}')
        elif key == 'space':
            self.drive.velocity(0.0, 0.0, sonar=self.sonar)
            self._say('command stop')
        elif key == 's':
            self.sonar = not self.sonar
            self.drive.velocity(tv, rv, sonar=self.sonar)
            self._say(f'sonar protection {"on" if self.sonar else "off"}')
        elif key == 'h':
            theta = self.heading.heading()
            if theta is None:
                self._say('no heading known: not holding one')
            else:
                self.drive.heading(tv, theta, sonar=self.sonar)
                self._say(f'holding heading {math.degrees(theta):.1f} deg at {tv:+.2f} m/s')
        elif key == 'a':
            self.drive.start_activity()
            self._say('start_activity')
        elif key == 'r':
            self.drive.release_robot()
            self._say('release_robot')
        elif key == 'q':
            self.drive.stop()
            self._say('quit')
            return False
        return True

    def show_status(self) -> None:
        """Print the status when it changes."""
        self.drive.update()
        self.heading.update()
        if self.drive.code is None:
            return
        tv, rv = self.drive.velocities or (0.0, 0.0)
        text = f'status {self.drive.code} ({CODES.get(self.drive.code, "?")}) tv {tv:+.2f} rv {rv:+.2f}'
        if text != self.shown:
            self.shown = text
            self._say(text)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('drive_i')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'b:').user
    try:
        keyboard = Keyboard(sys.stdin)
    except OSError as error:
        print(f'drive_i: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    drive = DriveProxy(manager)
    heading = HeadingSource(manager, user.get('b', 'PlutoBase'), lambda text: logger.warn(f'drive_i: {text}'))
    keys = DriveKeys(manager, drive, heading)
    set_loop(manager, LOOP_S)
    print(HELP.splitlines()[-1], flush=True)
    drive.command.wait_for_peers(5.0, channel='request')
    drive.start_activity()

    def step() -> None:
        keys.show_status()
        for key in keyboard.keys(0.0):
            if not keys.press(key):
                manager.set_state(RunState.QUIT)
                break

    def close() -> None:
        drive.command.wait_delivered(1.0)            # the last stop reaches the drive

    with keyboard:
        return run_loop(manager, step, close)


if __name__ == '__main__':
    sys.exit(main())
