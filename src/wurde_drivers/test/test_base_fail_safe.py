"""A base fails safe (issue 10, section 3), through the dummy base's real interfaces.

The brake is released only by an explicit Drive request; Twists and Pluto commands are refused
while it is set; NaN and infinite commands are refused; both drive interfaces reach one base; an
event published without a stamp never carries an earlier one.  Each refusal is observed in the
module's log before the next step, so the order of events across topics is known.
"""

from __future__ import annotations

import math
import pathlib
import time

import pytest
from geometry_msgs.msg import Twist
from sim_fixture import Observer, sim_config
from wurde_core import CommsManager
from wurde_core.interfaces import Egomotion
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.streams.base import BaseLimits, BaseStreams

WAIT_S = 30.0


@pytest.fixture
def base(ros_domain: int, tmp_path: pathlib.Path):  # type: ignore[no-untyped-def]
    path = sim_config(tmp_path)
    with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path),
                       '-n', 'PlutoBase']) as child:
        observer = Observer({'PlutoBaseDrive': 'RobotDrive',
                             'PlutoBaseDrive/SynchroDrive': 'SynchroDrive',
                             'PlutoBaseCommand': 'ActuatorState'})
        try:
            observer.until(lambda o: 'PlutoBaseDrive' in o.infos
                           and 'PlutoBaseDrive/SynchroDrive' in o.infos
                           and o.obj('PlutoBaseDrive').peers() > 0
                           and o.obj('PlutoBaseCommand').peers() > 0, 'the base', WAIT_S)
            yield child, observer
        finally:
            observer.close()


def _velocities(observer: Observer) -> list[tuple[float, float]]:
    """The commanded (linear, angular) velocities, rounded (ActuatorState carries float32)."""
    return [(round(m.velocity[0], 6), round(m.velocity[1], 6))
            for _, m in observer.events['PlutoBaseCommand']]


def _twist_until_logged(child: ChildProcess, observer: Observer, publisher, twist: Twist,
                        text: str) -> None:
    """Publish ``twist`` until the base logs ``text`` (the publisher may match late)."""
    deadline = time.monotonic() + WAIT_S
    while text not in child.stderr:
        assert time.monotonic() < deadline, f'the base never logged {text!r}:\n{child.stderr}'
        publisher.publish(twist)
        observer.manager.wait(0.05)
    observer.pump()


def _request_until_logged(child: ChildProcess, observer: Observer, stream: str, text: str,
                          **values: object) -> None:
    observer.request(stream, **values)
    deadline = time.monotonic() + WAIT_S
    while text not in child.stderr:
        assert time.monotonic() < deadline, f'the base never logged {text!r}:\n{child.stderr}'
        observer.manager.wait(0.05)
    observer.pump()


def test_only_an_explicit_drive_request_releases_the_brake(base) -> None:
    child, observer = base
    node = observer.manager.node
    cmd_vel = node.create_publisher(Twist, '/PlutoBase/cmd_vel', 10)
    observer.request('PlutoBaseDrive', brake=True)
    observer.until(lambda o: o.infos['PlutoBaseDrive'].brake, 'brake set', WAIT_S)
    forward = Twist()
    forward.linear.x = 0.3
    _twist_until_logged(child, observer, cmd_vel, forward,
                        'refused cmd_vel Twist: the brake is set')
    _request_until_logged(child, observer, 'PlutoBaseCommand',
                          'refused PlutoBaseCommand: the brake is set',
                          cmd_flags=0, velocity=[0.3, 0.0])
    info = observer.infos['PlutoBaseDrive']
    assert info.brake and info.trans_velocity == 0.0
    assert all(v == (0.0, 0.0) for v in _velocities(observer))
    # The explicit release, through the other drive interface (the typed view of the stream).
    observer.request('PlutoBaseDrive/SynchroDrive', brake=False)
    observer.until(lambda o: not o.infos['PlutoBaseDrive'].brake, 'brake released', WAIT_S)
    deadline = time.monotonic() + WAIT_S
    while (0.3, 0.0) not in _velocities(observer):
        assert time.monotonic() < deadline, 'a Twist did not move the base after the release'
        cmd_vel.publish(forward)
        observer.until(lambda o: True, 'pump')
        observer.manager.wait(0.05)
    assert not observer.infos['PlutoBaseDrive/SynchroDrive'].brake


def test_nan_and_infinite_commands_are_refused(base) -> None:
    child, observer = base
    node = observer.manager.node
    cmd_vel = node.create_publisher(Twist, '/PlutoBase/cmd_vel', 10)
    bad = Twist()
    bad.linear.x = math.nan
    _twist_until_logged(child, observer, cmd_vel, bad, 'refused cmd_vel Twist: not finite')
    _request_until_logged(child, observer, 'PlutoBaseDrive', 'refused RobotDrive request: not finite',
                          trans_velocity=math.inf)
    _request_until_logged(child, observer, 'PlutoBaseCommand',
                          'refused PlutoBaseCommand: not finite', cmd_flags=0,
                          velocity=[0.1, -math.inf])
    info = observer.infos['PlutoBaseDrive']
    assert math.isfinite(info.trans_velocity) and math.isfinite(info.rot_velocity)
    assert all(math.isfinite(a) and math.isfinite(b) for a, b in _velocities(observer))
    # A good command still works afterwards.
    observer.request('PlutoBaseDrive/SynchroDrive', trans=0.2, angular=0.0)
    observer.until(lambda o: (0.2, 0.0) in _velocities(o), 'a good command after the bad ones',
                   WAIT_S)


def test_an_event_without_a_stamp_is_stamped_when_published(ros_domain: int) -> None:
    manager = CommsManager('StampBase')
    manager.set_no_sleep()
    try:
        streams = BaseStreams('StampBase', synchro=False, limits=BaseLimits(1.0, 1.0, 1.0, 1.0),
                              command_timeout=1.0)
        streams.register(manager)
        consumer = Egomotion('StampBaseMotion')
        consumer.set_queue_mode(True)
        manager.register_consumer(consumer)
        assert streams.motion.wait_for_peers(WAIT_S)
        streams.publish_motion(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, stamp=100.0)
        before = time.time()
        streams.publish_motion(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        assert streams.motion.wait_delivered(WAIT_S)
        stamps = []
        deadline = time.monotonic() + WAIT_S
        while len(stamps) < 2:
            assert time.monotonic() < deadline, 'motion events did not arrive'
            manager.step()
            while consumer.get_next_data():
                stamps.append(consumer.data.timestamp.get_seconds())
            manager.wait(0.05)
        assert stamps[0] == 100.0
        assert stamps[1] >= before - 1e-6
    finally:
        manager.clean_up()
