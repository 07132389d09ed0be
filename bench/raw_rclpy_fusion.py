"""The localModule's traffic in raw rclpy, for ``bench/local_module_cpu.py``'s comparison.

A plain rclpy node (no WURDE) that subscribes to the simulated base's ``nav_msgs/Odometry`` and the
DMU's ``sensor_msgs/Imu`` (found by type on the graph) and, for every odometry message, publishes
what the localModule publishes per odometry sample: two pose streams (``nav_msgs/Odometry``, about
the size of a LocalizationPose), ``odom``, ``pose`` (PoseWithCovarianceStamped) and one ``/tf``
transform.  No estimation at all: it shows what the middleware alone costs at this rate.
Prints ``raw ready ODOMETRY-TOPIC IMU-TOPIC`` once subscribed.  Run by the benchmark, inside env.sh.
"""

from __future__ import annotations

import sys
import time

import rclpy
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from nav_msgs.msg import Odometry
from rclpy.executors import ExternalShutdownException
from sensor_msgs.msg import Imu
from tf2_msgs.msg import TFMessage

ODOMETRY, IMU = 'nav_msgs/msg/Odometry', 'sensor_msgs/msg/Imu'


def main() -> int:
    rclpy.init()
    node = rclpy.create_node('raw_rclpy_fusion')
    deadline = time.monotonic() + 60
    topics: dict[str, str] = {}
    while len(topics) < 2:
        for name, types in node.get_topic_names_and_types():
            for kind, word in ((ODOMETRY, 'Base'), (IMU, 'DMU')):
                if kind in types and word in name:
                    topics.setdefault(kind, name)
        if time.monotonic() > deadline:
            print(f'raw: no odometry and IMU topics ({topics})', flush=True)
            return 1
        time.sleep(0.2)
    outputs = [node.create_publisher(Odometry, f'/raw/stream{i}', 10) for i in range(2)]
    odom = node.create_publisher(Odometry, '/raw/odom', 10)
    pose = node.create_publisher(PoseWithCovarianceStamped, '/raw/pose', 10)
    tf = node.create_publisher(TFMessage, '/raw/tf', 10)

    def on_odometry(message: Odometry) -> None:
        for publisher in (*outputs, odom):
            publisher.publish(message)
        pose.publish(PoseWithCovarianceStamped(header=message.header, pose=message.pose))
        transform = TransformStamped(header=message.header, child_frame_id='base_link')
        transform.transform.translation.x = message.pose.pose.position.x
        transform.transform.rotation = message.pose.pose.orientation
        tf.publish(TFMessage(transforms=[transform]))

    node.create_subscription(Odometry, topics[ODOMETRY], on_odometry, 10)
    node.create_subscription(Imu, topics[IMU], lambda message: None, 10)
    print(f'raw ready {topics[ODOMETRY]} {topics[IMU]}', flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
