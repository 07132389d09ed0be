"""The sending process of the round-trip test: one Data and one Info message per interface.

Publishes deterministic messages (see roundtrip_fill) for every interface that wurde_interfaces
installs, prints READY, and keeps serving until stdin closes or it is interrupted.
"""

from __future__ import annotations

import sys
import threading

import rclpy
from rclpy.executors import ExternalShutdownException

import roundtrip_fill as rt
from wurde_idl import load_all


def main() -> int:
    rclpy.init()
    node = rclpy.create_node('wurde_roundtrip_peer')
    publishers = []
    for name, desc in sorted(load_all().items()):
        if desc['package'] != 'wurde_interfaces':
            continue
        for channel, message in (('data', desc['data_message']), ('info', desc['info_message'])):
            cls = rt.message_class(f'{desc["package"]}/{message}')
            publisher = node.create_publisher(cls, rt.topic(name, channel), rt.QOS)
            publisher.publish(rt.fill(cls, f'{name}.{channel}'))
            publishers.append(publisher)
    print(f'READY {len(publishers)}', flush=True)
    stop = threading.Event()
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
    try:
        while not stop.is_set() and rclpy.ok():
            rclpy.spin_once(node, timeout_sec=0.1)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
