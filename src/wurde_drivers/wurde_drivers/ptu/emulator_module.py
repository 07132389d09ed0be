"""ptu_emulator: an emulated PTU-46 on a pseudo-terminal, for trying the PTU Server without one.

``ptu_emulator -p /tmp/wurde-ptu`` links the emulated port at ``/tmp/wurde-ptu`` (the default),
which ``config/ptu/ptu-config.xml`` names as its port; the unit powers up as the real one does
(:class:`~wurde_drivers.ptu.emulator.PtuEmulator`). ``-s SECONDS``: how long a reset takes
(default 0).
"""

from __future__ import annotations

import sys

from ..emulator_host import run_emulator
from .emulator import PtuEmulator


def _make(options: dict[str, str]) -> PtuEmulator:
    text = options.get('s', '0')
    try:
        reset_s = float(text)
    except ValueError:
        reset_s = -1.0
    if not 0.0 <= reset_s <= 60.0:
        print(f'ptu_emulator: -s {text!r} is not a time of 0 to 60 s', file=sys.stderr)
        raise SystemExit(2)
    return PtuEmulator(reset_s=reset_s)


def main(argv: list[str] | None = None) -> int:
    """The ``ptu_emulator`` program: the emulated unit on a pty linked at ``-p`` until Quit.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (0, or 1 when the emulator's thread failed).
    """
    return run_emulator('ptu', _make, user_spec='s:', argv=argv,
                        help_text='  -s SECONDS  how long a reset (R) takes (default 0)')


if __name__ == '__main__':
    sys.exit(main())
