"""sick_emulator: a SICK LMS 2xx or PLS on a pseudo-terminal, for trying sick_server without the hardware.

The laser (``-k LMS`` or ``PLS``, :class:`~wurde_drivers.sick.emulator.SickEmulator`) stands in a
rectangular room: walls ``-w RIGHT,AHEAD,LEFT`` metres to its right, ahead and to its left
(default 1.2, 4.5, 2.5: a corridor-like room, asymmetric so a reversed scan shows), or sees a
circle of ``-d METRES`` everywhere. A reset (the end of a fatal error) takes ``-t SECONDS``
(default 1; a real one about 20 s, Pluto 8.1). The pty is linked at ``-p PATH`` (default
``/tmp/wurde-sick``), the port that ``config/sick/laser-config.xml`` names.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence

from ..emulator_host import run_emulator
from .emulator import ScanSource, SickEmulator, constant_source

__all__ = ['DEFAULT_ROOM', 'main', 'make', 'room_source']

#: Walls to the right, ahead and to the left of the scanner, metres.
DEFAULT_ROOM = (1.2, 4.5, 2.5)

HELP = ('  -k KIND     LMS (default) or PLS\n'
        '  -w R,A,L    room walls R m to the right, A m ahead, L m to the left (default '
        f'{",".join(f"{v:g}" for v in DEFAULT_ROOM)})\n'
        '  -d METRES   every beam reads METRES instead (a circle around the scanner)\n'
        '  -t SECONDS  how long a reset takes, default 1')


def room_source(right: float, ahead: float, left: float) -> ScanSource:
    """Ranges to the walls of a room: beam 0 at the right-hand end, counter-clockwise (as sent).

    :param right: metres from the scanner to the wall on its right.
    :param ahead: metres to the wall ahead.
    :param left: metres to the wall on its left.
    """
    def source(count: int, fov_deg: float) -> Sequence[float]:
        ranges = []
        for index in range(count):
            angle = math.radians(-fov_deg / 2 + fov_deg * index / max(count - 1, 1))
            c, s = math.cos(angle), math.sin(angle)
            hits = [ahead / c] if c > 1e-9 else []
            if s > 1e-9:
                hits.append(left / s)
            elif s < -1e-9:
                hits.append(right / -s)
            ranges.append(min(hits))
        return ranges
    return source


def _fail(text: str) -> None:
    print(f'sick_emulator: {text}', file=sys.stderr, flush=True)
    sys.exit(2)


def _positive(letter: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value <= 0:
        _fail(f'-{letter} {text!r} is not a positive number')
    return value


def make(options: dict[str, str]) -> SickEmulator:
    """The emulator the options describe (exits with status 2 on a bad value).

    :param options: the program's own options by letter: ``k`` (LMS or PLS), ``w``
        (``RIGHT,AHEAD,LEFT``), ``d`` (metres everywhere, wins over ``w``), ``t`` (reset seconds).
    """
    kind = options.get('k', 'LMS')
    if kind not in ('LMS', 'PLS'):
        _fail(f'-k {kind!r} is not LMS or PLS')
    if 'd' in options:
        source = constant_source(_positive('d', options['d']))
    else:
        walls = options.get('w', ','.join(map(str, DEFAULT_ROOM))).split(',')
        if len(walls) != 3:
            _fail(f'-w {options["w"]!r} is not RIGHT,AHEAD,LEFT')
        right, ahead, left = (_positive('w', wall) for wall in walls)
        source = room_source(right, ahead, left)
    reset_s = _positive('t', options.get('t', '1'))
    return SickEmulator(kind=kind, scan_source=source, reset_s=reset_s)


def main(argv: list[str] | None = None) -> int:
    """The ``sick_emulator`` program: the emulator on a pty linked at ``-p`` until Quit.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (0, or 1 when the emulator's thread failed).
    """
    return run_emulator('sick', make, user_spec='k:w:d:t:', help_text=HELP, argv=argv)


if __name__ == '__main__':
    sys.exit(main())
