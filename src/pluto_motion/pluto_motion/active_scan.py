"""Where the motionModule points the wrist (Pluto 4: "It controls the wrist as well in order to do
active scanning, moving the laser to see to the side or the ground"); pure, no I/O.

Pan is counter-clockwise from the robot's front (left > 0), tilt < 0 looks down (rad).  Per what
the motionModule does:

* wall follow passed down to the avoidModule (avoid cmdFlags 3, 13, 23, 33): pan left, level —
  Pluto 6.2: "One should turn the wrist to the left so the laser gets a good view of the wall
  near the camera";
* moveto by ray following, following a ray: the wrist looks right and left in turn, :data:`SIDE`
  each way for :data:`SWEEP_S` each (6.3: "checking both sides, right and left, as it goes to find
  any openings"); scanning for new paths: ahead, level (the far view);
* moveto on the map's plan, explore, investigate approaching: ahead, level;
* any moveto on its last stretch (the simple goto, element[2] -2): ahead, down to the ground;
* investigate once at the object (its "unfold arm" step, done with the wrist on a robot without an
  arm) and circling: at the object's centre, down (:data:`GROUND`);
* nothing of these: no aim (the wrist is the user's; :class:`pluto_motion.wrist_link.WristLink`
  brings it back to rest once).
"""

from __future__ import annotations

import dataclasses
import math

from .motion_behaviours import Explore, Investigate, Moveto
from .motion_command import FOLLOWING, NEARING, SCANNING

__all__ = ['GROUND', 'LEFT', 'SIDE', 'SWEEP_S', 'Aim', 'aim_for', 'is_wall_follow']

#: Pan of "turn the wrist to the left" (rad).
LEFT = math.pi / 2
#: Pan each side while a ray is followed (rad).
SIDE = 0.8
#: Seconds on each side while a ray is followed.
SWEEP_S = 2.0
#: Tilt that brings the scan plane down to the ground a few metres ahead (rad, down).
GROUND = -0.3


@dataclasses.dataclass(frozen=True)
class Aim:
    """A wrist position (pan, tilt; rad) and why, for the log."""

    pan: float
    tilt: float
    why: str


def is_wall_follow(cmd_flags: int) -> bool:
    """Whether a command passed to the avoidModule is its wall follow (Pluto 6.2: T = 3)."""
    return 0 <= cmd_flags < 40 and cmd_flags % 10 == 3


def _ahead(why: str) -> Aim:
    return Aim(0.0, 0.0, why)


def aim_for(behaviour: Moveto | Investigate | Explore | None, element3: int | None, element2: int,
            wall_follow: bool, pose: tuple[float, float, float] | None, now: float) -> Aim | None:
    """The wrist's aim while ``behaviour`` runs with status codes ``element3`` and ``element2``
    (``wall_follow``: the avoidModule follows a wall at the motionModule's command); None: no aim."""
    if behaviour is None:
        return Aim(LEFT, 0.0, 'wall follow: left, to the wall') if wall_follow else None
    if isinstance(behaviour, Investigate):
        centre = behaviour.centre
        if behaviour.approached and centre is not None and pose is not None:
            bearing = math.atan2(centre[1] - pose[1], centre[0] - pose[0]) - pose[2]
            return Aim(math.remainder(bearing, math.tau), GROUND, 'investigate: at the object (for the arm)')
        return _ahead('investigate: approaching')
    if isinstance(behaviour, Moveto):
        if element2 == NEARING:
            return Aim(0.0, GROUND, 'moveto: nearing the goal, the ground ahead')
        if behaviour.planner is None and element3 == FOLLOWING:
            side = 1.0 if int(now // SWEEP_S) % 2 == 0 else -1.0
            return Aim(side * SIDE, 0.0, 'ray following: right and left in turn, for openings')
        if behaviour.planner is None and element3 == SCANNING:
            return _ahead('ray following: scanning for new paths')
        return _ahead('moveto: ahead')
    return _ahead('explore: ahead')
