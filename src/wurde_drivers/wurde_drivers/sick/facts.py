"""Facts of the SICK LMS 2xx / PLS that the driver, the emulator, the stream contract and the
dummy laser all need, stated once (docs/protocols.md section 1, Pluto 8.1).

- **Beam counts**: a 180° scan has 181 values at 1° and 361 at 0.5° (1.6); Pluto's ``N/RWI``
  stream carries the 181 of a 1° scan.
- **Mirror**: the mirror turns at 75 Hz; 0.5° is interlaced over 2 sweeps, so a scan takes
  ``sweeps / 75`` s of mirror (1.6), and it cannot go out faster than its telegram's bytes at 10
  bits a byte on the line.
- **Range table**: a value is 13 bits and 8183..8191 are error codes, 8183 meaning "value >
  maximum" (1.6), so the largest range an LMS reports is 8182 units: 81.82 m in cm mode and
  8.182 m in mm mode.  A PLS reads to 50 m (CARMEN, 1.7) and runs at 0.5° in cm only (Player
  forces 180°/0.5°, 1.7).

Pure Python: no rclpy, no wurde_core, so the simulator may use it too.
"""

from __future__ import annotations

from . import codec

__all__ = ['FOV_DEG', 'KINDS', 'MIRROR_HZ', 'RWI_VALUES', 'UNITS', 'VALUES_AT', 'centre_offset_s',
           'max_range_m', 'scan_period_s', 'sweeps', 'variant_error', 'wire_time_s']

#: Degrees one scan covers (the variants we run; 100° exists, docs/protocols.md 1.5).
FOV_DEG = 180
#: Mirror turns per second.
MIRROR_HZ = 75.0
#: Values per 180° scan by the resolution in degrees.
VALUES_AT = {1.0: 181, 0.5: 361}
#: Values of Pluto's ``N/RWI`` stream: a 1° scan.
RWI_VALUES = VALUES_AT[1.0]
#: Device types and the units the drivers run them in.
KINDS = ('LMS', 'PLS')
UNITS = ('cm', 'mm')
#: Largest range in metres by (type, units): the last value below the error codes for an LMS.
_MAX_RANGE_M = {('LMS', units): round((codec.VALUE_TOO_FAR - 1) * codec.UNIT_SCALE[units], 6)
                for units in UNITS}
_MAX_RANGE_M[('PLS', 'cm')] = 50.0


def variant_error(kind: str, values: int, units: str) -> str | None:
    """Why ``kind`` cannot scan ``values`` values per 180° in ``units``, or None if it can.

    :param kind: ``'LMS'`` or ``'PLS'``.
    :param values: 181 or 361.
    :param units: ``'cm'`` or ``'mm'``.
    """
    if kind not in KINDS:
        return f'laser type {kind!r} is not LMS or PLS'
    if values not in VALUES_AT.values():
        return f'{values} values per scan is not 181 (1°) or 361 (0.5°)'
    if units not in UNITS:
        return f'laser units {units!r} are not cm or mm'
    if kind == 'PLS' and (values != VALUES_AT[0.5] or units != 'cm'):
        return 'a PLS runs at 0.5° (361 values) in cm only'
    return None


def max_range_m(kind: str, units: str) -> float:
    """Largest range (m) a ``kind`` reports in ``units``; farther reads as "value > maximum".

    :param kind: ``'LMS'`` or ``'PLS'``.
    :param units: ``'cm'`` or ``'mm'``.
    :raises KeyError: a type and units the device does not run in (see :func:`variant_error`).
    """
    return _MAX_RANGE_M[(kind, units)]


def sweeps(values: int) -> int:
    """Mirror sweeps per 180° scan (0.5° is interlaced over 2).

    :param values: values per scan, 181 or 361.
    """
    return codec.interlace(FOV_DEG * 100 // (values - 1))


def wire_time_s(values: int, baud: int) -> float:
    """Seconds a B0 telegram takes on the line (10 bits a byte).

    :param values: values per scan.
    :param baud: the line speed.
    """
    return codec.telegram_size(values) * 10.0 / baud


def scan_period_s(values: int, baud: int) -> float:
    """Seconds between two scans streamed: the mirror's sweeps or the telegram's time on the wire,
    whichever is longer.

    :param values: values per scan, 181 or 361.
    :param baud: the line speed.
    """
    return max(sweeps(values) / MIRROR_HZ, wire_time_s(values, baud))


def centre_offset_s(values: int, baud: int) -> float:
    """Seconds from the middle of a scan to the arrival of its telegram's last byte: the wire time,
    then half of one mirror sweep.  At 38400 baud with 361 values that is 190.6 + 6.7 ≈ 197 ms,
    Pluto 8.1's "about 200 ms earlier".

    :param values: values per scan.
    :param baud: the line speed.
    """
    return wire_time_s(values, baud) + 0.5 / MIRROR_HZ
