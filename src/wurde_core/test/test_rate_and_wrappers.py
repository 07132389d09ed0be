"""Rate control and heartbeat settings, and the ObstacleAvoider / VectorMover wrappers."""

from __future__ import annotations

import math
import time

import pytest

from conftest import until
from wurde_core import CommsManager, Point, PVector
from wurde_core.interfaces import ObstacleAvoider, VectorMover, robot_object_class


def test_sleep_sets_the_ttl_and_the_loop_period(ros_domain: int) -> None:
    manager = CommsManager('Rate')
    try:
        assert manager.sleep_time() == 0.1 and manager.ttl() == pytest.approx(0.2)  # defaults
        manager.set_sleep(0.15)
        assert manager.ttl() == pytest.approx(0.3)
        manager.set_sleep_only(0.05)
        assert manager.ttl() == pytest.approx(0.3) and manager.sleep_time() == 0.05
        manager.set_heartbeat_only(1.5)
        assert manager.ttl() == 1.5
        manager.set_pre_sleep()
        start = time.monotonic()
        for _ in range(4):
            manager.run_update()
        assert time.monotonic() - start >= 4 * 0.05
        manager.set_no_sleep()
        assert manager.sleep_time() == 0.0
    finally:
        manager.clean_up()


def test_no_heartbeat_means_no_heartbeat_stream(ros_domain: int) -> None:
    manager = CommsManager('Silent')
    try:
        manager.set_no_heartbeat()
        manager.step()
        topics = [name for name, _ in manager.node.get_topic_names_and_types()]
        assert not any('heartbeat' in name for name in topics)
        assert manager._heartbeat is None
    finally:
        manager.clean_up()


def test_obstacle_avoider_verbs_reach_the_supplier(manager: CommsManager) -> None:
    transport = robot_object_class('ObstacleAvoiderTransport')('Avoider')
    transport.set_queue_mode(True)
    manager.register_supplier(transport)
    avoider = ObstacleAvoider('Avoider')
    manager.register_consumer(avoider)
    until(manager, lambda: avoider.peers() > 0, what='match')
    assert avoider.move_to_relative_point(Point(1.5, -0.5))
    assert avoider.rotate_to_relative_angle(-math.pi / 2)
    assert avoider.stop()
    got = []

    def collect() -> bool:
        while transport.get_next_request():
            got.append((transport.requests.mode.get_value(), transport.requests.goal.get_value(),
                        transport.requests.angle.get_value(),
                        sorted(transport.requests.ros_message().set_fields)))
        return len(got) == 3

    until(manager, collect, what='three requests')
    assert got[0][0] == 1 and got[0][1] == Point(1.5, -0.5) and got[0][3] == ['goal', 'mode']
    assert got[1][0] == 2 and got[1][2] == -math.pi / 2 and got[1][3] == ['angle', 'mode']
    assert got[2][0] == 0 and got[2][3] == ['mode']


def test_vector_mover_moves_and_stops(manager: CommsManager) -> None:
    transport = robot_object_class('VectorMoverTransport')('Mover')
    transport.set_queue_mode(True)
    manager.register_supplier(transport)
    mover = VectorMover('Mover')
    manager.register_consumer(mover)
    until(manager, lambda: mover.peers() > 0, what='match')
    assert mover.move_to(1.0, 1.0)
    assert mover.stop()
    got = []

    def collect() -> bool:
        while transport.get_next_request():
            got.append((transport.requests.vector.get_value(),
                        transport.requests.brake.get_value()))
        return len(got) == 2

    until(manager, collect, what='two requests')
    assert got[0][0] == PVector(math.sqrt(2.0), math.pi / 4) and got[0][1] is False
    assert got[1][0] == PVector(0.0, 0.0) and got[1][1] is True
