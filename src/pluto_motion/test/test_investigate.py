"""Pluto 6.3's investigate (motion cmdFlags 43) through real processes: the whole simulated Pluto
(config/pluto's noise, localModule, poseModule, the chain) in a generated room with a box in it.
From the start the box is the nearest object: element[3] says 11 (approaching), then 12
(circling), element[2] 2 when done; the truth goes round the box on all four sides without ever
coming closer to it or a wall than the robot's radius, and the arm step is logged as unavailable."""

from __future__ import annotations

import math
import pathlib

from motion_fixture import RADIUS, Commander, pluto, pluto_config
from pluto_nav.loc_proxy import LocProxy
from pluto_nav.streams import POSE, POSE_SETTER

from pluto_motion.motion_command import APPROACHING, CIRCLING, INVESTIGATE_DONE

BOX = (6.0, 7.0)
ROOM = f"""<?xml version="1.0"?>
<!-- A 12 m x 10 m room with a 0.6 m box 3 m ahead of the start. -->
<map name="box-room" version="1.0">
  <bounds xmin="0" ymin="0" xmax="12" ymax="10"/>
  <polyline points="0,0 12,0 12,10 0,10" closed="true"/>
  <polyline points="{BOX[0] - 0.3},{BOX[1] - 0.3} {BOX[0] + 0.3},{BOX[1] - 0.3}
                   {BOX[0] + 0.3},{BOX[1] + 0.3} {BOX[0] - 0.3},{BOX[1] + 0.3}" closed="true"/>
  <place name="start" x="6" y="4" theta="{math.pi / 2}"/>
</map>
"""


def test_investigate_approaches_and_circles_the_nearest_object(ros_domain: int, tmp_path: pathlib.Path) -> None:
    room = tmp_path / 'box-room.xml'
    room.write_text(ROOM)
    directory = pluto_config(tmp_path, room)
    c = Commander(room)
    m = c.motion
    loc = LocProxy(c.manager, 1 << POSE)
    try:
        with pluto(directory, '-m', 'map.xml') as processes:
            c.children = processes
            c.until(lambda: m.motion_status is not None and len(c.truths) > 0, 'motion status and truth', timeout=120)
            c.until(lambda: m.goto_status not in (None, -10), 'the avoid thread runs', every=m.start_activity)
            c.until(lambda: loc.setter == POSE_SETTER and loc.get_pose(POSE) is not None, 'the poseModule localizes',
                    timeout=120)

            mark, start = len(c.statuses), len(c.truths)
            c.until(lambda: any(s.element[3] == APPROACHING for s in c.statuses[mark:]), 'approaching',
                    every=m.investigate, period=2.0)
            try:
                c.until(lambda: any(s.element[2] == INVESTIGATE_DONE for s in c.statuses[mark:]), 'investigate done',
                        timeout=240)
            except AssertionError as error:
                raise AssertionError(f"{error}\nmotion:\n{processes['motion'].stderr[-4000:]}\navoid:\n"
                                     f"{processes['avoid'].stderr[-4000:]}\nstatuses: "
                                     f"{[(list(s.element), list(s.data)) for s in c.statuses[mark:][:40]]}") from None
            codes = [int(s.element[3]) for s in c.statuses[mark:]]
            assert APPROACHING in codes and CIRCLING in codes, processes['motion'].stderr[-3000:]
            assert codes.index(APPROACHING) < codes.index(CIRCLING)
            sides = {int(math.atan2(y - BOX[1], x - BOX[0]) // (math.pi / 2)) for x, y, _ in c.truths[start:]}
            assert sides == {-2, -1, 0, 1}, sides
            assert c.closest_to_walls(start) >= RADIUS
            assert 'the arm step (unfold the arm) is not available' in processes['motion'].stderr
    finally:
        c.close()
