"""Which NMEA GGA fix qualities make a good fix (Pluto Software Documentation 8.4).

Pluto 8.4: "the quality should be 2 for sub-meter accuracy".  The GGA quality is a code, not a
scale, so "at least 2" must not be read as a number: 6 (dead reckoning), 7 (manual input) and
8 (simulation) are larger numbers that measure nothing, and 0 is no fix at all.  Only the five
measured kinds count, in the order of their accuracy:

====== ============== =====================================================
rank   GGA quality    what
====== ============== =====================================================
1      1              GPS (standard positioning), a few metres
2      3              PPS (precise positioning service)
3      2              DGPS: sub-metre, Pluto's "quality 2"
4      5              RTK float: decimetres
5      4              RTK fixed: centimetres
====== ============== =====================================================

A fix meets a minimum quality when its rank is at least the minimum's: with Pluto's minimum 2 a
good fix is DGPS (2), RTK float (5) or RTK fixed (4) — never 6.  Minimum 0 takes any measured
fix.  Pure functions, no ROS.
"""

from __future__ import annotations

__all__ = ['ACCURACY_ORDER', 'MINIMUMS', 'meets']

#: The measured GGA qualities, least accurate first.
ACCURACY_ORDER = (1, 3, 2, 5, 4)
#: What a minimum quality may be: 0 (any measured fix) or one of :data:`ACCURACY_ORDER`.
MINIMUMS = (0, *ACCURACY_ORDER)


def meets(quality: int, minimum: int) -> bool:
    """Whether a fix of GGA ``quality`` is at least as accurate as ``minimum`` requires.

    :param quality: the fix's GGA quality; 0 (no fix) and 6 (dead reckoning) never meet any minimum.
    :param minimum: 0 (any measured fix) or one of :data:`ACCURACY_ORDER`.
    :raises ValueError: ``minimum`` is not one of :data:`MINIMUMS` (e.g. 6: dead reckoning is
        never a requirement).
    """
    if minimum not in MINIMUMS:
        raise ValueError(f'minimum fix quality must be one of {MINIMUMS}, not {minimum}')
    if quality not in ACCURACY_ORDER:
        return False
    return minimum == 0 or ACCURACY_ORDER.index(quality) >= ACCURACY_ORDER.index(minimum)
