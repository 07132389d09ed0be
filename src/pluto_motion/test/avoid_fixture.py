"""Helpers for the avoidModule tests: a simulated Pluto (exact odometry) in a map of wall segments,
the dummy base and laser, the localModule, the driveModule and the avoidModule as real processes,
and a test-side module with an AvoidProxy that also records the truth and the drive's echoes."""

from __future__ import annotations

import contextlib
import math
import pathlib
from collections.abc import Iterator, Sequence
from typing import Any

from drive_fixture import Driver, program, room_config
from goto_sim import Segment, clearance

from pluto_motion.avoid_proxy import AvoidProxy

RADIUS = 0.35


def write_world(directory: pathlib.Path, size: tuple[float, float], walls: Sequence[Segment],
                start: tuple[float, float, float]) -> list[Segment]:
    """config/pluto's simulation (exact odometry) in ``directory`` with a map of the outer walls of
    a ``size`` room and ``walls``; every segment of the map, for truth clearances."""
    room_config(directory)
    w, h = size
    inner = '\n'.join(f'  <wall x1="{a}" y1="{b}" x2="{c}" y2="{d}"/>' for a, b, c, d in walls)
    (directory / 'map.xml').write_text(f"""<?xml version="1.0"?>
<map name="avoid" version="1.0">
  <bounds xmin="0" ymin="0" xmax="{w}" ymax="{h}"/>
  <polyline points="0,0 {w},0 {w},{h} 0,{h}" closed="true"/>
{inner}
  <place name="start" x="{start[0]}" y="{start[1]}" theta="{start[2]}"/>
</map>
""")
    return [(0, 0, w, 0), (w, 0, w, h), (w, h, 0, h), (0, h, 0, 0), *walls]


@contextlib.contextmanager
def chain(directory: pathlib.Path, *avoid_args: str) -> Iterator[dict[str, Any]]:
    """Dummy base and laser, localModule, driveModule and avoidModule, stopped at the end."""
    with program('wurde_drivers', 'dummy_base', directory, '-n', 'PlutoBase') as base, \
            program('wurde_drivers', 'dummy_sick', directory, '-n', 'PlutoLaser') as laser, \
            program('pluto_nav', 'local_module', directory, '-m', 'map.xml') as local, \
            program('pluto_motion', 'drive_module', directory) as drive, \
            program('pluto_motion', 'avoid_module', directory, *avoid_args) as avoid:
        yield {'base': base, 'laser': laser, 'local': local, 'drive': drive, 'avoid': avoid}


class Avoider(Driver):
    """The test's module: an AvoidProxy (queue mode) besides the Driver's DriveProxy, truth and
    base command."""

    def __init__(self) -> None:
        super().__init__()
        self.avoid = AvoidProxy(self.manager, queue_mode=True)
        self.avoid_statuses: list[Any] = []
        #: The truth's least distance to a wall of :attr:`walls` so far.
        self.lowest = math.inf
        self.checked = 0
        self.walls: list[Segment] = []

    def pump(self) -> None:
        super().pump()
        self.avoid_statuses.extend(self.avoid.update())
        if self.walls:
            for message in self.truths[self.checked:]:
                self.lowest = min(self.lowest, clearance(self.walls, message.location.x, message.location.y))
        self.checked = len(self.truths)

    def ready(self) -> float:
        """Wait until the chain is up: avoid and drive statuses heard, the truth moving in, and the
        avoidModule steering on the localModule's Dead-Reckoning (not on the base odometry it
        uses before the localModule is heard, whose frame starts at the origin)."""
        return self.until(lambda: self.avoid.code is not None and self.drive.code == 0 and self.pose is not None
                          and 'steer on Localization/Dead-Reckoning' in self.children['avoid'].stderr,
                          'avoid and drive status, the truth and the pose source', timeout=60)
