"""Helpers for the CARMEN API tests: a CARMEN program's connection and a robot-side module in this
process, on real DDS, and a pump that runs both until a condition holds."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from typing import Any

from wurde_core import CommsManager, Pose, RobotObject, Time
from wurde_core.interfaces import Egomotion

from pluto_motion.carmen import carmen_ipc_disconnect, carmen_ipc_initialize, carmen_ipc_sleep
from pluto_motion.carmen.ipc import CarmenIpc

#: Longest wait for a stream's peers (discovery on a loaded machine).
PEERS_S = 30.0


@contextlib.contextmanager
def carmen_and_robot() -> Iterator[tuple[CarmenIpc, CommsManager]]:
    """The CARMEN program's connection and the robot module ``Robot`` (suppliers), both closed."""
    robot = CommsManager('Robot')
    robot.set_no_sleep()
    ipc = carmen_ipc_initialize(['carmen_test'])
    try:
        yield ipc, robot
    finally:
        carmen_ipc_disconnect()
        robot.clean_up()


def supply(robot: CommsManager, obj: RobotObject, *, queue: bool = True) -> RobotObject:
    """Register ``obj`` as a supplier of ``robot`` (queue mode: a burst reaches a queue reader)."""
    obj.set_queue_mode(queue)
    obj.set_auto_timestamp(False)
    robot.register_supplier(obj)
    return obj


def until(test: Callable[[], Any], what: str, timeout: float = 30.0,
          robot: CommsManager | None = None, every: Callable[[], object] | None = None) -> Any:
    """Run the CARMEN program's loop (and ``robot``'s, and ``every``) until ``test()`` is true."""
    deadline = time.monotonic() + timeout
    while True:
        if robot is not None:
            robot.step()
        if every is not None:
            every()
        value = test()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f'{what}: not within {timeout} s')
        assert carmen_ipc_sleep(0.02) == 0


def odometry_supplier(robot: CommsManager, name: str = 'PlutoBaseMotion') -> Egomotion:
    """A base's odometry stream, supplied by ``robot`` with stamps the test sets."""
    return supply(robot, Egomotion(name))


def send_odometry(ego: Egomotion, stamp: float, x: float, y: float = 0.0, theta: float = 0.0,
                  tv: float = 0.0, rv: float = 0.0) -> None:
    """One odometry sample at ``stamp`` (s), acceleration 0.25 m/s²."""
    ego.data.location = Pose(x, y, theta)
    ego.data.tv, ego.data.rv, ego.data.acceleration = tv, rv, 0.25
    ego.data.timestamp = Time(stamp)
    assert ego.publish_data()
