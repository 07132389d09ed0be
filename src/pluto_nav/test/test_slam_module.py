"""slamModule with the simulated Pluto (noise on), all real processes: Pluto 7.2's procedure.

The thread waits to be started, then holds setter 2 while it maps; ``element[1] = 2`` saves the
map (-1 while saving, 0 after, the cycle goes on); stopping the thread saves it again and gives the
setter back.  The saved map lies on the true walls, its ``start`` is where the robot was, and a
poseModule loaded with it keeps the Pose on the truth as the robot drives on.
"""

from __future__ import annotations

import math
import pathlib

from nav_fixture import Watcher, angle_error, interpolate_truth, module, pluto_config, processes, seconds
from slam_sim import wall_errors
from wurde_drivers.sim.world import World

from pluto_nav.streams import STREAMS
from wurde_idl.mapfile import load_map_data

POSE = STREAMS[3]
ALL = ['PlutoBase', 'PlutoLaser', 'PlutoDMU', 'PlutoWrist']
STATUS = 'slam/status'


def _position_error(watcher: Watcher) -> float:
    truth = watcher.events['PlutoBaseTruth']
    for message in reversed(watcher.events[POSE]):
        true = interpolate_truth(truth, seconds(message))
        if true is not None:
            return math.hypot(message.pose.x - true[0], message.pose.y - true[1])
    return math.inf


def test_slam_module_maps_saves_on_command_and_on_stop_and_the_map_localizes(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    directory = pluto_config(tmp_path)          # config/pluto: office, odometry/laser/DMU noise on
    output = tmp_path / 'maps' / 'slam.xml'
    watcher = Watcher({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseDrive': 'RobotDrive', POSE: 'LocalizationPose',
                       STATUS: 'FVectorState'})
    status = watcher.objects[STATUS]
    events = watcher.events

    def drive(trans: float, rot: float = 0.0) -> None:
        obj = watcher.objects['PlutoBaseDrive']
        obj.requests.trans_velocity.set_value(trans)
        obj.requests.rot_velocity.set_value(rot)
        obj.publish_request()

    def request(element: list[int]) -> None:
        status.requests.element.set_value(element)
        status.publish_request()

    def element(i: int) -> float:
        return events[STATUS][-1].element[i] if events[STATUS] else math.nan

    def drive_until(predicate, what: str, trans: float, rot: float = 0.0) -> None:
        watcher.until(predicate, what, timeout=120, every=lambda: drive(trans, rot))
        watcher.until(lambda: abs(events['PlutoBaseTruth'][-1].tv) < 1e-6
                      and abs(events['PlutoBaseTruth'][-1].rv) < 1e-6,
                      'stopped', every=lambda: drive(0.0))

    def truth():
        return events['PlutoBaseTruth'][-1].location

    try:
        with processes(directory, ALL, ('local_module', []), ('slam_module', ['-f', str(output)])):
            # Pluto 7.2: the thread does not start by itself.
            watcher.until(lambda: events[STATUS] and events[POSE] and events['PlutoBaseTruth'],
                          'status, Pose and truth', timeout=90)
            assert element(0) == 0 and events[POSE][-1].cmd_flags == 0
            start = truth()
            watcher.until(lambda: element(0) == 1, 'the thread runs', every=lambda: request([1]))
            watcher.until(lambda: events[POSE][-1].cmd_flags == 2, 'the slam module holds setter 2')
            # Map: 4 m east along the corridor, a half turn, two metres back west.
            drive_until(lambda: truth().x > start.x + 4.0, 'four metres east', 0.4)
            drive_until(lambda: angle_error(truth().theta, start.theta) > math.radians(170), 'facing west', 0.0, 0.5)
            drive_until(lambda: truth().x < start.x + 2.0, 'two metres back west', 0.4)
            assert _position_error(watcher) < 0.10
            # element[1] = 2 saves: -1 while saving, then 0; the thread runs on with setter 2.
            request([1, 2])
            watcher.until(lambda: element(1) == 0 and events[STATUS][-1].data[2] == 1, 'map saved once')
            assert any(m.element[1] == -1 for m in events[STATUS]), 'element[1] was never -1 while saving'
            watcher.until(lambda: events[POSE][-1].cmd_flags == 2, 'setter 2 again after the save')
            assert element(0) == 1
            saved = load_map_data(output)
            world = World.from_map_data(load_map_data(directory / 'map.xml'))
            assert len(saved.walls) >= 4, saved.walls
            errors = wall_errors(saved.walls, world)
            assert errors.max() < 0.10, errors       # bench/slam_offline.py's target
            x, y, theta = saved.places['start']
            assert math.hypot(x - start.x, y - start.y) < 0.05 and abs(theta - start.theta) < math.radians(1.0)
            # Stopping the thread saves the map again and releases the setter.
            watcher.until(lambda: element(0) == 0, 'the thread stopped', every=lambda: request([0]))
            watcher.until(lambda: events[STATUS][-1].data[2] == 2, 'saved on stop')
            watcher.until(lambda: events[POSE][-1].cmd_flags == 0, 'setter released')
            # The map SLAM made is a poseModule's a-priori map.
            with module('pluto_nav', 'pose_module', directory, '-m', str(output)):
                watcher.until(lambda: events[POSE][-1].cmd_flags == 1, 'the pose module holds setter 1', timeout=90)
                drive_until(lambda: truth().x < start.x + 0.5, 'on west with the saved map', 0.4)
                watcher.until(lambda: _position_error(watcher) < 0.08, 'the Pose on the truth', timeout=30)
    finally:
        watcher.close()
