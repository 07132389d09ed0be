"""rflex_emulator: an emulated rFLEX base on a pseudo-terminal, for trying rflex_server without one.

``rflex_emulator -p /tmp/wurde-rflex`` links the emulated port at ``/tmp/wurde-rflex`` (the
default), which ``config/rflex/rflex-config.xml`` names as the port of its ``base`` device. The
base powers up with the brake set and obeys the real protocol
(:class:`~wurde_drivers.rflex.emulator.RFlexEmulator`). Options::

    -t TYPE      robot type: B21r (default), B21ir, ATRVJr or ATRV2, as rflex-config.xml's type
    -v VOLTS     battery voltage the base reports (default 26)
    -s METRES    range every sonar reads (default: no echo)
"""

from __future__ import annotations

import math
import sys

from ..emulator_host import run_emulator
from .emulator import RFlexEmulator
from .robots import ROBOTS

__all__ = ['main']

_HELP = '\n'.join(line[2:] for line in __doc__.splitlines() if line.startswith('    -'))


def _refuse(message: str) -> None:
    print(f'rflex_emulator: {message}', file=sys.stderr, flush=True)
    raise SystemExit(2)


def _number(options: dict[str, str], key: str, default: float, low: float, high: float) -> float:
    text = options.get(key)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not low <= value <= high:
        _refuse(f'-{key} {text!r} must be a number from {low:g} to {high:g}')
    return value


def make(options: dict[str, str]) -> RFlexEmulator:
    """The emulator the options describe (exits with status 2 on a bad value).

    :param options: the program's own options by letter: ``t`` (robot type), ``v`` (volts, 0-60),
        ``s`` (metres every sonar reads, 0-20; absent: no echo).
    """
    kind = options.get('t', 'B21r')
    if kind not in ROBOTS:
        _refuse(f'-t {kind!r} is not a robot type ({", ".join(ROBOTS)})')
    voltage = _number(options, 'v', 26.0, 0.0, 60.0)
    sonar = _number(options, 's', math.inf, 0.0, 20.0)   # not given: no echo
    robot = ROBOTS[kind]
    ranges = [sonar] * len(robot.sonars)
    return RFlexEmulator(robot, voltage=voltage, sonar_ranges=lambda: ranges)


def main(argv: list[str] | None = None) -> int:
    """The ``rflex_emulator`` program: the emulated base on a pty linked at ``-p`` until Quit.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (0, or 1 when the emulator's thread failed).
    """
    return run_emulator('rflex', make, user_spec='t:v:s:', help_text=_HELP, argv=argv)


if __name__ == '__main__':
    sys.exit(main())
