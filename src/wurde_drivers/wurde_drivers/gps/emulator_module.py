"""gps_emulator: an emulated NMEA GPS receiver on a pseudo-terminal, for trying the GPS module.

``gps_emulator -p /tmp/wurde-gps`` links the emulated port at ``/tmp/wurde-gps`` (the default),
which ``config/gps/gps-config.xml`` names as its port. The receiver drives a slow circle, so
successive fixes differ (:func:`circle`), and writes GGA + RMC
(:class:`~wurde_drivers.gps.emulator.GpsEmulator`). Options::

    -C LAT,LON   centre of the circle in degrees (default 59.3498,18.0707)
    -R METRES    radius of the circle (default 20)
    -T SECONDS   time for one lap (default 120; about 1 m/s)
    -f HZ        fixes per second (default 1)
    -b BAUD      line speed: 4800 (default), 9600 or 38400
    -s COUNT     satellites in use (default 8)
    -q QUALITY   GGA fix quality (default 2, DGPS: a good fix for Pluto 8.4)
"""

from __future__ import annotations

import math
import sys

from ..emulator_host import run_emulator
from .emulator import GpsEmulator, GpsSample, PositionSource
from .geo import LocalFrame

CENTRE = (59.3498, 18.0707)
ALTITUDE = 30.0

_HELP = '\n'.join(line[2:] for line in __doc__.splitlines() if line.startswith('    -'))


def circle(latitude: float, longitude: float, radius: float, period: float,
           altitude: float = ALTITUDE) -> PositionSource:
    """Counter-clockwise (seen from above) round a centre: east of it at time 0, north of it a quarter
    ``period`` later; speed and course follow the motion.

    :param latitude: the centre's, degrees.
    :param longitude: the centre's, degrees.
    :param radius: m.
    :param period: seconds a turn takes.
    :param altitude: metres above MSL reported throughout.
    """
    frame = LocalFrame(latitude, longitude, altitude)
    omega = 2.0 * math.pi / period

    def source(elapsed: float) -> GpsSample:
        angle = omega * elapsed
        lat, lon = frame.from_xy(radius * math.cos(angle), radius * math.sin(angle))
        # Velocity (-sin, cos) in (east, north): its course from north, clockwise, is -angle.
        course = math.degrees(-angle) % 360.0
        return GpsSample(lat, lon, altitude, abs(radius * omega), course)
    return source


def _number(options: dict[str, str], key: str, default: float, low: float, high: float) -> float:
    text = options.get(key)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not low <= value <= high:
        print(f'gps_emulator: -{key} {text!r} must be a number from {low:g} to {high:g}',
              file=sys.stderr)
        raise SystemExit(2)
    return value


def _make(options: dict[str, str]) -> GpsEmulator:
    centre = CENTRE
    if 'C' in options:
        parts = options['C'].split(',')
        values = [_number({'C': part}, 'C', 0.0, -180.0, 180.0) for part in parts]
        if len(values) != 2 or abs(values[0]) > 90.0:
            print(f'gps_emulator: -C {options["C"]!r} must be LAT,LON in degrees', file=sys.stderr)
            raise SystemExit(2)
        centre = (values[0], values[1])
    radius = _number(options, 'R', 20.0, 0.0, 10_000.0)
    period = _number(options, 'T', 120.0, 1.0, 86_400.0)
    baud = _number(options, 'b', 4800, 4800, 38400)
    if baud not in (4800, 9600, 38400):
        print(f'gps_emulator: -b {options["b"]!r} must be 4800, 9600 or 38400', file=sys.stderr)
        raise SystemExit(2)
    return GpsEmulator(circle(centre[0], centre[1], radius, period),
                       rate_hz=_number(options, 'f', 1.0, 0.1, 50.0), baudrate=int(baud),
                       satellites=int(_number(options, 's', 8, 0, 64)),
                       quality=int(_number(options, 'q', 2, 0, 9)))


def main(argv: list[str] | None = None) -> int:
    """The ``gps_emulator`` program: the emulated receiver on a pty linked at ``-p`` until Quit.

    :param argv: the command line, program name first; None: ``sys.argv``.
    :returns: the exit status (0, or 1 when the emulator's thread failed).
    """
    return run_emulator('gps', _make, user_spec='C:R:T:f:b:s:q:', help_text=_HELP, argv=argv)


if __name__ == '__main__':
    sys.exit(main())
