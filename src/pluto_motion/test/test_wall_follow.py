"""The avoidModule's wall follow (avoid cmdFlags 3 + 10 A, Pluto 6.2) through real processes: the
whole simulated Pluto (config/pluto's noise, localModule, poseModule, the chain) in a generated
room, the wall on the robot's left.  Along the straight wall the camera (back-left of the robot,
:data:`pluto_motion.wall_follow.CAMERA`) holds the distance asked for; at the inside corner the
robot turns right and follows the next wall; nowhere is the truth closer to a wall than the
robot's radius."""

from __future__ import annotations

import math
import pathlib

from motion_fixture import RADIUS, Commander, pluto, pluto_config

from pluto_motion.avoid_proxy import AvoidProxy
from pluto_motion.wall_follow import CAMERA

DISTANCE = 0.8
#: A 10 m x 6 m room; the robot starts 1.2 m from its south wall, facing west (the wall on its left).
ROOM = f"""<?xml version="1.0"?>
<map name="wall-room" version="1.0">
  <bounds xmin="0" ymin="0" xmax="10" ymax="6"/>
  <polyline points="0,0 10,0 10,6 0,6" closed="true"/>
  <place name="start" x="8.5" y="1.2" theta="{math.pi}"/>
</map>
"""


def _camera(pose: tuple[float, float, float]) -> tuple[float, float]:
    x, y, theta = pose
    return (x + CAMERA[0] * math.cos(theta) - CAMERA[1] * math.sin(theta),
            y + CAMERA[0] * math.sin(theta) + CAMERA[1] * math.cos(theta))


def test_wall_follow_holds_the_camera_at_its_distance_and_turns_the_corner(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    room = tmp_path / 'wall-room.xml'
    room.write_text(ROOM)
    directory = pluto_config(tmp_path, room)
    c = Commander(room)
    avoid = AvoidProxy(c.manager)
    try:
        with pluto(directory, '-m', 'map.xml') as processes:
            c.children = processes
            c.until(lambda: avoid.goto_status not in (None, -10) and len(c.truths) > 0, 'the avoid thread runs',
                    every=lambda: (avoid.update(), avoid.start_activity()), timeout=120)
            start = len(c.truths)
            c.until(lambda: c.speeds[-1] > 0.1, 'following the wall',
                    every=lambda: (avoid.update(), avoid.wall_follow(0.3, DISTANCE)), period=2.0)
            c.until(lambda: c.truths[-1][0] < 1.5 and c.truths[-1][1] > 2.5, 'round the corner and north',
                    every=avoid.update, timeout=180)
            avoid.stop()
            along = [p for p in c.truths[start:] if 3.0 <= p[0] <= 6.5 and p[1] < 2.0]
            assert len(along) > 10
            worst = max(abs(_camera(p)[1] - DISTANCE) for p in along)      # the south wall is y = 0
            assert worst < 0.1, worst
            assert all(abs(math.remainder(p[2] - math.pi, math.tau)) < math.radians(10) for p in along)
            assert c.closest_to_walls(start) >= RADIUS
    finally:
        c.close()
