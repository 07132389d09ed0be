"""The publishing process of the round-trip test.

Publishes tree.static() once on /tf_static (transient local), prints READY, then tree.dynamic()
on /tf every 50 ms, as a TF broadcaster does, until interrupted (SIGINT, as ChildProcess.stop).
"""

from __future__ import annotations

import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from tf2_msgs.msg import TFMessage

import tree


def main() -> int:
    rclpy.init()
    node = rclpy.create_node('tf2_msgs_roundtrip_peer')
    static = node.create_publisher(TFMessage, '/tf_static', tree.TF_STATIC_QOS)
    dynamic = node.create_publisher(TFMessage, '/tf', tree.TF_QOS)
    static.publish(tree.static())
    node.create_timer(0.05, lambda: dynamic.publish(tree.dynamic()))
    print('READY', flush=True)
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
