"""motionModule with the whole simulated Pluto on the office map (config/pluto: noise, localModule,
poseModule, drive, avoid), all real processes, driven through MotionProxy: a rectangle set shows
element[3] = -1, an unreachable goal ends with element[2] = 3, a moveto from the corridor into a
room reaches the goal without the simulator's truth ever closer to a wall than the robot's radius,
a velocity command passes through to avoid, NaN and unknown flags are refused and counted, and a
release stops the thread (-10).  ``max_tv`` is a tunable: set to 0.3 m/s while the module runs,
the next moveto goes no faster."""

from __future__ import annotations

import math
import pathlib
import time

from motion_fixture import RADIUS, Commander, pluto, pluto_config, program
from nav_msgs.msg import Path
from wurde_testing.topics import latched
from wurde_testing.parameters import ParameterTool

from pluto_motion.avoid_command import COMMAND as AVOID_COMMAND
from pluto_motion.motion_proxy import MotionProxy
from pluto_motion.task import TaskResult

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'


def test_moveto_across_a_door_and_the_status_codes(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, OFFICE)
    c = Commander(OFFICE)
    m = c.motion
    try:
        with pluto(directory, '-m', 'map.xml') as processes:
            c.children = processes
            c.until(lambda: m.motion_status is not None and len(c.truths) > 0, 'motion status and truth', timeout=120)
            c.until(lambda: m.goto_status not in (None, -10), 'the avoid thread runs', every=m.start_activity)

            # The rectangle: set -> -1; removed -> 0 (Pluto 6.3).
            c.until(lambda: m.motion_status == -1, 'rectangle set',
                    every=lambda: m.set_rectangle(9.0, 8.0, 10.0, 7.5, -math.pi / 2))
            c.until(lambda: m.motion_status == 0, 'rectangle removed', every=lambda: m.set_rectangle(0.0, 0.0))

            # Unreachable: inside the lab's off-limits work cell.
            task = m.go_to(14.0, 3.5, timeout=60)
            c.until(task.is_task_complete, 'unreachable moveto ends')
            assert task.result() is TaskResult.FAILED and m.moveto_status == 3
            assert 'unreachable' in processes['motion'].stderr

            # Refusals are counted (data[2]).
            before = m.refused
            m.send(42, position=[math.nan, 1.0])
            m.send(41)
            c.until(lambda: m.refused == before + 2, 'NaN and 41 refused')

            # The speed is a tunable (0.6 m/s from -v): 0.3 for the next moveto; 5 is refused.
            tool = ParameterTool('/motionModule')
            try:
                assert tool.get('max_tv', 'reach') == [0.6, 0.25]
                taken, reason = tool.set('max_tv', 5.0)
                assert not taken and 'out of range' in reason
                assert tool.set('max_tv', 0.3) == (True, '')
            finally:
                tool.close()

            # Corridor (start 3, 7.5) -> office2 (7.5, 3) through its 0.9 m door.
            start = len(c.truths)
            task = m.go_to(7.5, 3.0, timeout=240)
            c.until(task.is_task_complete, 'moveto office2', timeout=260)
            assert task.result() is TaskResult.SUCCEEDED, (task.reason, m.element)
            assert math.dist(c.truths[-1][:2], (7.5, 3.0)) < 0.4
            assert c.closest_to_walls(start) >= RADIUS
            assert 0.2 < max(c.speeds[start:]) <= 0.3 + 1e-3          # float32 on the wire
            codes = {tuple(s.element[2:4]) for s in c.statuses}
            assert (-1, 3) in codes or (-1, 1) in codes                  # moveto set, following
            assert any(s.element[2] == -2 for s in c.statuses)           # nearing: the simple goto
            assert not any(s.element[0] in (1, 2) for s in c.statuses)   # no bumper
            # /plan (nav_msgs/Path, transient local): this late reader gets the plan to office2.
            plan = latched('/plan', Path)
            assert plan.header.frame_id == 'map' and len(plan.poses) >= 3
            points = [(p.pose.position.x, p.pose.position.y) for p in plan.poses]
            assert math.dist(points[-1], (7.5, 3.0)) < 0.05 and math.dist(points[0], c.truths[start][:2]) < 0.5

            # Pass-through: a velocity command (cmdFlags 0) reaches the drive.
            c.until(lambda: m.velocities is not None and m.velocities[0] > 0.05, 'driven by a pass-through',
                    every=lambda: m.send(0, velocity=[0.1, 0.0]), period=0.5)
            m.stop()

            # Release: motion (and avoid) threads stop.
            c.until(lambda: m.motion_status == -10, 'released', every=m.release_robot)
            c.until(lambda: m.goto_status == -10, 'avoid released too')
    finally:
        c.close()


def test_a_passed_down_command_waits_for_the_avoid_module(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The motionModule accepts (echoes) a pass-through velocity command while no avoidModule is
    there; the avoidModule that comes later still gets it, held until its reader was matched
    (a command published before then is lost: the request channel keeps nothing)."""
    from wurde_core import CommsManager
    from wurde_core.interfaces import ActuatorState

    tester = CommsManager('MotionTest')
    tester.set_no_sleep()
    motion = MotionProxy(tester)
    avoid: CommsManager | None = None
    try:
        with program('pluto_motion', 'motion_module', tmp_path):
            def until(test, what: str, timeout: float = 60.0) -> None:
                deadline = time.monotonic() + timeout
                while not test():
                    assert time.monotonic() < deadline, f'{what}: not within {timeout} s'
                    tester.step()
                    motion.update()                  # sends what waited for the motionModule
                    if avoid is not None:
                        avoid.step()
                    tester.wait(0.02)

            motion.send(0, velocity=[0.1, 0.0])
            until(lambda: any(e.cmd_flags == 0 and math.isclose(e.velocity[0], 0.1, abs_tol=1e-4)
                              for e in motion.echoes()), 'the motionModule\'s echo')
            avoid = CommsManager('avoidModule')
            avoid.set_no_sleep()
            avoid.set_no_heartbeat()
            command = ActuatorState(AVOID_COMMAND)
            command.set_queue_mode(True)
            avoid.register_supplier(command)
            got: list[tuple[int, list[float]]] = []

            def take() -> bool:
                while command.get_next_request():
                    got.append((int(command.requests.cmd_flags.get_value()),
                                [round(v, 4) for v in command.requests.velocity.get_value()]))
                return (0, [0.1, 0.0]) in got

            until(take, 'the pass-through command at the late avoidModule')
    finally:
        if avoid is not None:
            avoid.clean_up()
        tester.clean_up()
