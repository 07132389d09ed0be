"""TFMessage crosses real DDS from another process on /tf and /tf_static, as RViz would see it.

The subscriber also reads what DDS discovery announced for the publisher: the type name and the
RIHS01 type hash a stock ROS 2 Jazzy tool compares against its own tf2_msgs.
"""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable

from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from tf2_msgs.msg import TFMessage
from wurde_testing import ChildProcess

import tree
import upstream

HERE = pathlib.Path(__file__).parent
DEADLINE_S = 30.0


def spin_until(executor: SingleThreadedExecutor, done: Callable[[], bool],
               peer: ChildProcess) -> None:
    deadline = time.monotonic() + DEADLINE_S
    while not done() and time.monotonic() < deadline and peer.process.poll() is None:
        executor.spin_once(timeout_sec=0.1)


def test_tf_and_tf_static_arrive_from_another_process(rclpy_context: Context) -> None:
    node = Node('tf2_msgs_roundtrip_test', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    got: dict[str, TFMessage] = {}
    try:
        node.create_subscription(TFMessage, '/tf', lambda m: got.setdefault('/tf', m),
                                 tree.TF_QOS)
        with ChildProcess([str(HERE / 'tf_peer.py')]) as peer:
            peer.expect('READY')
            # Subscribed only now: the static transform was sent before, and must still come.
            node.create_subscription(TFMessage, '/tf_static',
                                     lambda m: got.setdefault('/tf_static', m),
                                     tree.TF_STATIC_QOS)
            spin_until(executor, lambda: len(got) == 2, peer)
            publishers = {topic: node.get_publishers_info_by_topic(topic)
                          for topic in ('/tf', '/tf_static')}
            code = peer.stop()
        assert code in (0, -2), f'peer failed ({code}):\n{peer.stderr}'
        assert got.get('/tf') == tree.dynamic(), f'/tf: {got.get("/tf")}'
        assert got.get('/tf_static') == tree.static(), f'/tf_static: {got.get("/tf_static")}'
        for topic, infos in publishers.items():
            assert len(infos) == 1, f'{topic}: {infos}'
            assert infos[0].topic_type == upstream.TYPE_NAME
            assert str(infos[0].topic_type_hash) == upstream.TYPE_HASH
    finally:
        executor.shutdown()
        node.destroy_node()
