"""A small recording of a ROS 2 robot that never heard of WURDE, for ros_inputs' bag test: the
simulated office (config/maps/office.xml) seen by a 270-degree laser mounted upside down, and an
odometry whose heading drifts, written as an MCAP file the way wurde_mcp's ``record`` writes one
(raw CDR, each channel with its type's ros2msg definition, durability and reliability in its
metadata), so that wurde_mcp's ``replay`` plays it.

The robot stands for :data:`STAND_S`, then drives east along the corridor, weaving.  The truth is
kept (:class:`Bag`), in the odometry's frame: both start at the origin where the robot starts.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np
from geometry_msgs.msg import TransformStamped
from mcap.writer import Writer
from nav_msgs.msg import Odometry
from rclpy.serialization import serialize_message
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage
from wurde_core.ros_messages import set_stamp
from wurde_mcp.recording.schema import message_definition

from wurde_drivers.sim.mapfile import load_map

ROOT = pathlib.Path(__file__).resolve().parents[3]
OFFICE = ROOT / 'config' / 'maps' / 'office.xml'
#: Bag time of the first message (s): a robot's clock, not ours.
T0 = 1_700_000_000.0
STAND_S, DRIVE_S = 2.0, 8.0
STEP_S = 0.01
ODOM_EVERY, TF_EVERY, SCAN_EVERY = 2, 5, 10          # 50 Hz, 20 Hz, 10 Hz
BEAMS, FOV, RANGE_MIN, RANGE_MAX = 1081, math.radians(270.0), 0.05, 25.0
#: A turn of the mirror per scan period: the time between two of its beams.
TIME_INCREMENT = SCAN_EVERY * STEP_S / 1440
#: The odometry's heading error: rad/s added to the turn rate it reports.
HEADING_BIAS = 0.04
#: base_link -> laser_mount -> laser (upside down under its bracket).
MOUNT = {'laser_mount': ('base_link', (0.15, 0.0, 0.30), (0.0, 0.0, 0.0)),
         'laser': ('laser_mount', (0.05, 0.0, 0.05), (math.pi, 0.0, 0.0))}
LASER_X = 0.20                 # the laser's distance ahead of the robot's centre


@dataclasses.dataclass
class Bag:
    """What was written: the truth (stamp, x, y, theta) in the odometry's frame, the scans' centre
    stamps and the odometry as recorded."""

    truth: list[tuple[float, float, float, float]]
    scan_centres: list[float]
    odometry: list[tuple[float, float, float, float]]
    messages: int = 0

    def truth_at(self, stamp: float) -> tuple[float, float, float]:
        times = [t for t, *_ in self.truth]
        index = min(range(len(times)), key=lambda i: abs(times[i] - stamp))
        return self.truth[index][1:]


def _velocity(t: float) -> tuple[float, float]:
    if t < STAND_S:
        return 0.0, 0.0
    return 0.4, 0.15 * math.sin(2 * math.pi * (t - STAND_S) / 4.0)


def _quaternion(yaw: float) -> tuple[float, float, float, float]:
    return 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)


def _edge(parent: str, child: str, stamp: float, xyz: tuple[float, float, float],
          rotation: tuple[float, float, float, float]) -> TransformStamped:
    t = TransformStamped()
    set_stamp(t, stamp)
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = rotation
    return t


class _Sink:
    """Channels as ``record`` opens them; messages as rclpy serializes them."""

    def __init__(self, writer: Writer) -> None:
        self.writer = writer
        self.channels: dict[str, int] = {}
        self.count = 0

    def channel(self, topic: str, type_name: str, *, latched: bool = False, best_effort: bool = False) -> None:
        schema = self.writer.register_schema(type_name, 'ros2msg', message_definition(type_name).encode())
        self.channels[topic] = self.writer.register_channel(topic, 'cdr', schema, {
            'durability': 'transient_local' if latched else 'volatile',
            'reliability': 'best_effort' if best_effort else 'reliable'})

    def write(self, topic: str, stamp: float, message: object) -> None:
        ns = round(stamp * 1e9)
        self.writer.add_message(self.channels[topic], log_time=ns, publish_time=ns,
                                data=serialize_message(message), sequence=self.count)
        self.count += 1


def write_bag(path: pathlib.Path, *, seed: int = 7) -> Bag:
    """Write the recording to ``path``; return what it holds."""
    world = load_map(OFFICE)
    start = world.places['start']
    rng = np.random.default_rng(seed)
    laser_angles = -FOV / 2 + FOV / (BEAMS - 1) * np.arange(BEAMS)
    bag = Bag([], [], [])
    with open(path, 'wb') as stream:
        writer = Writer(stream)
        writer.start(profile='ros2', library='ros_inputs test')
        sink = _Sink(writer)
        sink.channel('/tf_static', 'tf2_msgs/msg/TFMessage', latched=True)
        sink.channel('/tf', 'tf2_msgs/msg/TFMessage')
        sink.channel('/odom', 'nav_msgs/msg/Odometry')
        sink.channel('/scan', 'sensor_msgs/msg/LaserScan', best_effort=True)
        sink.write('/tf_static', T0, TFMessage(transforms=[
            _edge(parent, child, T0, xyz, tuple(Rotation.from_euler('xyz', rpy).as_quat()))
            for child, (parent, xyz, rpy) in MOUNT.items()]))
        x = y = theta = 0.0                       # truth, odometry frame
        ox = oy = otheta = 0.0                    # the odometry's own
        steps = round((STAND_S + DRIVE_S) / STEP_S)
        for step in range(steps + 1):
            t = step * STEP_S
            stamp = T0 + t
            if step:
                tv, rv = _velocity(t - STEP_S)
                x, y = x + tv * STEP_S * math.cos(theta), y + tv * STEP_S * math.sin(theta)
                theta += rv * STEP_S
                orv = rv + (HEADING_BIAS if tv else 0.0)
                ox, oy = ox + tv * STEP_S * math.cos(otheta), oy + tv * STEP_S * math.sin(otheta)
                otheta += orv * STEP_S
            bag.truth.append((stamp, x, y, theta))
            tv, rv = _velocity(t)
            if step % ODOM_EVERY == 0:
                odom = Odometry()
                set_stamp(odom, stamp)
                odom.header.frame_id, odom.child_frame_id = 'odom', 'base_link'
                odom.pose.pose.position.x, odom.pose.pose.position.y = ox, oy
                q = odom.pose.pose.orientation
                q.x, q.y, q.z, q.w = _quaternion(otheta)
                odom.twist.twist.linear.x, odom.twist.twist.angular.z = tv, rv
                sink.write('/odom', stamp, odom)
                bag.odometry.append((stamp, ox, oy, otheta))
            if step % TF_EVERY == 0:
                sink.write('/tf', stamp, TFMessage(transforms=[
                    _edge('odom', 'base_link', stamp, (ox, oy, 0.0), _quaternion(otheta))]))
            if step % SCAN_EVERY == 0 and step > 0:
                # the scan around this instant, raycast from the truth (map frame) at its centre
                mx = start.x + x * math.cos(start.theta) - y * math.sin(start.theta)
                my = start.y + x * math.sin(start.theta) + y * math.cos(start.theta)
                heading = start.theta + theta
                origin = (mx + LASER_X * math.cos(heading), my + LASER_X * math.sin(heading))
                ranges = world.raycast(origin, heading - laser_angles, max_range=RANGE_MAX)  # upside down
                ranges = ranges + rng.normal(0.0, 0.01, BEAMS) * (ranges < RANGE_MAX)
                ranges[::97] = math.nan                     # dazzled beams
                scan = LaserScan()
                set_stamp(scan, stamp - (BEAMS - 1) / 2 * TIME_INCREMENT)
                scan.header.frame_id = 'laser'
                scan.angle_min, scan.angle_max = -FOV / 2, FOV / 2
                scan.angle_increment = FOV / (BEAMS - 1)
                scan.time_increment, scan.scan_time = TIME_INCREMENT, SCAN_EVERY * STEP_S
                scan.range_min, scan.range_max = RANGE_MIN, RANGE_MAX
                scan.ranges = ranges.astype(np.float32).tolist()
                sink.write('/scan', stamp, scan)
                bag.scan_centres.append(stamp)
        writer.finish()
    bag.messages = sink.count
    return bag
