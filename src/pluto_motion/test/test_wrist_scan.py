"""The motionModule turns the wrist (Pluto 4's active scanning) through real processes: the
motionModule (``-m map.xml -R``) and the dummy wrist of config/pluto.  A wall follow passed down
turns the wrist left (Pluto 6.2), also when the wrist comes up after the command; a stop brings it
back to rest, after which it is the user's: a position the user sets stays."""

from __future__ import annotations

import math
import pathlib
import time

from motion_fixture import pluto_config, program
from wurde_core import CommsManager
from wurde_core.interfaces import ActuatorState

from pluto_motion.active_scan import LEFT
from pluto_motion.motion_proxy import MotionProxy

OFFICE = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps' / 'office.xml'


def test_wall_follow_turns_the_wrist_left_and_a_stop_gives_it_back(ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path, OFFICE)
    manager = CommsManager('WristScanTest')
    manager.set_no_sleep()
    motion = MotionProxy(manager)
    wrist = ActuatorState('PlutoWrist')
    manager.register_consumer(wrist)
    at: list[tuple[float, float]] = []

    def until(predicate, what: str, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while not predicate():
            assert time.monotonic() < deadline, f'{what}: not within {timeout} s; wrist at {at[-1:]}'
            manager.step()
            motion.update()
            while wrist.get_next_data():
                at.append(tuple(float(v) for v in wrist.data.position[:2]))
            manager.wait(0.05)

    def near(pan: float, tilt: float) -> bool:
        return bool(at) and abs(at[-1][0] - pan) < 0.02 and abs(at[-1][1] - tilt) < 0.02

    try:
        with program('pluto_motion', 'motion_module', directory, '-m', 'map.xml', '-R') as mover:
            until(lambda: motion.motion_status is not None, 'the motionModule is heard', timeout=120)
            motion.send(33, [0.3], [0.8])                      # wall follow, 0.8 m (avoid type 3, A = 3)
            until(lambda: motion.echo is not None and motion.echo[0] == 33, 'the wall follow accepted')
            assert 'moveto by ray following (-R)' in mover.stderr
            assert 'active scanning on' not in mover.stderr   # no wrist yet, and the module runs on
            with program('wurde_drivers', 'dummy_wrist', directory, '-n', 'PlutoWrist'):
                until(lambda: near(LEFT, 0.0), 'the wrist turned left', timeout=120)
                assert 'wrist PlutoWrist found: active scanning on' in mover.stderr
                motion.stop()
                until(lambda: near(0.0, 0.0), 'the wrist back at rest')
                request = wrist.requests                       # the user takes the wrist
                request.cmd_flags.set_value(0)
                request.position.set_value([-0.5, 0.2])
                request.velocity.set_value([1.0, 1.0])
                request.acceleration.set_value([2.0, 2.0])
                wrist.publish_request()
                until(lambda: near(-0.5, 0.2), 'the wrist where the user put it')
                held = len(at)
                until(lambda: len(at) > held + 60, 'three more seconds of wrist states')   # 20 Hz
                assert all(math.dist(p, (-0.5, 0.2)) < 0.02 for p in at[held:])
                assert mover.process.poll() is None
    finally:
        manager.clean_up()
