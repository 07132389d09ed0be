"""Pure pursuit along a plan (pluto_motion.path_follow), on a unicycle whose heading turns at a
limited rate (as the drive's regulator does): through a 0.9 m door from a corridor, the robot keeps
inside the planning grid's free cells, and the progress watchdog fires only without progress."""

from __future__ import annotations

import math

from pluto_motion.grid_planner import Planner
from pluto_motion.path_follow import FollowSettings, PathFollower, Progress
from pluto_motion.planning_grid import build_grid

#: A room 8 m x 6 m split by a wall at y = 3 with a 0.9 m door at x 5.55..6.45.
WALLS = [(0, 0, 8, 0), (8, 0, 8, 6), (8, 6, 0, 6), (0, 6, 0, 0), (0, 3, 5.55, 3), (6.45, 3, 8, 3)]
DT, MAX_RV = 0.05, 1.0


def drive(follower: PathFollower, pose: tuple[float, float, float], steps: int = 4000):
    path = [pose]
    for _ in range(steps):
        if math.dist(pose[:2], follower.goal) < 0.1:
            break
        heading, speed = follower.command(pose, 0.6)
        error = math.atan2(math.sin(heading - pose[2]), math.cos(heading - pose[2]))
        theta = pose[2] + max(-MAX_RV * DT, min(MAX_RV * DT, 1.5 * error * DT))
        pose = (pose[0] + speed * DT * math.cos(theta), pose[1] + speed * DT * math.sin(theta), theta)
        path.append(pose)
    return path


def test_through_a_door_from_the_side_down_its_middle() -> None:
    grid = build_grid(WALLS, bounds=(0, 0, 8, 6))
    start, goal = (1.0, 1.5), (6.0, 5.0)
    plan = Planner(grid).plan(start, goal)
    assert plan.reachable
    path = drive(PathFollower(start, plan.waypoints, FollowSettings(), grid.clearance_at), (*start, 0.0))
    assert math.dist(path[-1][:2], goal) < 0.1
    assert all(grid.free_at(x, y) for x, y, _ in path)
    in_door = [x for x, y, _ in path if abs(y - 3.0) < 0.15]
    assert in_door and max(abs(x - 6.0) for x in in_door) < 0.03     # 0.04 without the narrow rule


def test_progress_fires_only_without_progress() -> None:
    watch = Progress(FollowSettings(progress=0.2, patience=5.0))
    assert not watch.stuck(10.0, 0.0)
    assert not watch.stuck(9.7, 4.0)           # 0.3 m nearer: progress
    assert not watch.stuck(9.6, 8.0)           # 0.1 m in 4 s: still patient
    assert watch.stuck(9.6, 9.5)               # no 0.2 m in 5.5 s
