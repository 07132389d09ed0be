"""dmu_emulator: a Crossbow DMU on a pseudo-terminal, for trying dmu_module without the hardware.

The unit lies level and turns slowly about the vertical at a constant yaw rate (``-w``, rad/s,
counter-clockwise seen from above, i.e. about the robot's z-up axis; default 0.1), so the filtered
stream's heading theta grows steadily. The emulator speaks in the sensor's own z-down frame
(:mod:`wurde_drivers.dmu.emulator`); the module turns it into the robot frame. The pty is linked
at ``-p PATH`` (default ``/tmp/wurde-dmu``), the port that ``config/dmu/dmu-config.xml`` names.
"""

from __future__ import annotations

import math
import sys

from ..emulator_host import run_emulator
from .emulator import DmuEmulator, constant_rate

__all__ = ['main']

HELP = ('  -w RAD_S  yaw rate about the vertical (z up), default 0.1\n'
        '  -f HZ     packets per second in continuous mode, default 100')


def _number(options: dict[str, str], letter: str, default: float, *, positive: bool) -> float:
    text = options.get(letter)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or (positive and value <= 0):
        print(f'dmu_emulator: -{letter} {text!r} is not a {"positive " if positive else ""}number',
              file=sys.stderr, flush=True)
        sys.exit(2)
    return value


def make(options: dict[str, str]) -> DmuEmulator:
    """The emulator the options describe (exits with status 2 on a bad value).

    :param options: the program's own options by letter: ``w`` (yaw rate, rad/s about z up),
        ``f`` (packets per second).
    """
    yaw_rate = _number(options, 'w', 0.1, positive=False)
    rate_hz = _number(options, 'f', 100.0, positive=True)
    # sensor frame z down: a counter-clockwise turn seen from above is a negative z rate
    return DmuEmulator(motion_source=constant_rate(-yaw_rate), rate_hz=rate_hz)


def main(argv: list[str] | None = None) -> int:
    """The ``dmu_emulator`` program: the emulated unit on a pty linked at ``-p`` until Quit.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (0, or 1 when the emulator's thread failed).
    """
    return run_emulator('dmu', make, user_spec='w:f:', help_text=HELP, argv=argv)


if __name__ == '__main__':
    sys.exit(main())
