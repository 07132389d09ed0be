"""The laser commands of AURS's help list: ``laser laserOnConnect`` and ``laserdata laserobst``
(AU Robot Servers, "Online help").

In AURS, ``laser`` and ``laserOnConnect`` are an ``if`` module aliased ``laser``: the camera
server's connection to the laser scanner server.  This server has the same (:mod:`.interface`,
loaded at start as ``module load=if alias=laser`` would), so it can connect to a Mobotware laser
server or another xmlServer.  ``laserdata`` and ``laserobst`` answer from this server's own laser
(``laser.ranges``, Pluto's SICK): ``laserdata`` gives the newest scan, ``laserobst`` answers as AURS
does without an obstacle resource (this server finds no obstacles in the scan).
"""

from __future__ import annotations

import math

from .command import Command, reply
from .session import Session
from .variables import VariablePool, format_value

__all__ = ['LASERDATA_HELP', 'LASEROBST_HELP', 'RANGES', 'LaserData', 'laser_obstacles']

#: The variable ``laserdata`` answers from.
RANGES = 'laser.ranges'

LASERDATA_HELP = ('----------- available LASERDATA options\n'
                  '(none)            The newest scan: serial (scans so far), count, unit (m)\n'
                  '                  and ranges="r0 r1 ..."\n'
                  'help              This help tekst\n'
                  '-----\n'
                  "See also 'laser' (an interface to a laser server) and 'var laser'")

LASEROBST_HELP = ('----------- available LASEROBST options\n'
                  'help              This help tekst\n'
                  '(this server has no obstacle resource: it finds no obstacles in the scan)')


class LaserData:
    """The ``laserdata`` handler over one pool."""

    def __init__(self, pool: VariablePool) -> None:
        self._pool = pool

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        if command.args:
            return [reply(tag, [('warning', 'Unknown option: '
                                            f'{" ".join(key for key, _ in command.args)}')])]
        var = self._pool.find(RANGES)
        value = var.current() if var is not None else []
        ranges = [float(v) for v in value] if isinstance(value, list) else []  # type: ignore[arg-type]
        serial = self._pool.updates(RANGES)
        if var is None or not ranges or not serial or not all(map(math.isfinite, ranges)):
            return [reply(tag, [('warning', 'No resources, missing laser scan (no scan in '
                                            f'{RANGES} yet)')])]
        return [reply(tag, [('name', 'scan'), ('serial', str(serial)), ('count', str(len(ranges))),
                            ('unit', 'm'), ('ranges', format_value('d', ranges)[0])])]


def laser_obstacles(client: Session, command: Command) -> list[str]:
    """``laserobst``: AURS's reply without an obstacle resource."""
    return [reply(command.tag, [('warning', 'No obstacle resource (this server finds no '
                                            'obstacles in the laser scan)')])]
