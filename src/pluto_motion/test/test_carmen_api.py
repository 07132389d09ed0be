"""CARMEN's robot-program API (pluto_motion.carmen) against real streams: the subscribe modes
(latest, all, unsubscribe), the NULL message (static memory) and NULL handler (memory only)
semantics of Programming with CARMEN 3.0.1, each message's fields and units from our streams,
the robot's laser message placed by the odometry, the navigator's autonomous_stopped events and
queries, timers, and the refusals of bad calls."""

from __future__ import annotations

import math
import signal
import time

import pytest
from carmen_fixture import PEERS_S, carmen_and_robot, odometry_supplier, send_odometry, supply, until
from wurde_core import Point, Pose, Time
from wurde_core.errors import InvalidValueError, NotRegisteredError
from wurde_core.interfaces import Bumper, NavigatorTransport, RangeFinder
from wurde_testing import ChildProcess

from pluto_motion.carmen import (CARMEN_NAVIGATOR_GOAL_REACHED_v, CARMEN_NAVIGATOR_UNKNOWN_v,
                                 CARMEN_NAVIGATOR_USER_STOPPED_v, CARMEN_SUBSCRIBE_ALL, CARMEN_SUBSCRIBE_LATEST,
                                 CARMEN_UNSUBSCRIBE, carmen_base_odometry_message,
                                 carmen_base_subscribe_bumper_message, carmen_base_subscribe_ir_message,
                                 carmen_base_subscribe_odometry_message, carmen_base_subscribe_sonar_message,
                                 carmen_ipc_addPeriodicTimer, carmen_ipc_disconnect, carmen_ipc_dispatch,
                                 carmen_ipc_sleep,
                                 carmen_laser_subscribe_frontlaser_message, carmen_laser_subscribe_rearlaser_message,
                                 carmen_navigator_go, carmen_navigator_query_plan, carmen_navigator_query_status,
                                 carmen_navigator_set_goal, carmen_navigator_stop,
                                 carmen_navigator_subscribe_autonomous_stopped_message,
                                 carmen_navigator_subscribe_plan_message, carmen_navigator_subscribe_status_message,
                                 carmen_robot_subscribe_frontlaser_message, carmen_robot_velocity_command)

def test_latest_hands_over_the_newest_in_a_static_message_with_carmens_units(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        seen = []
        static = carmen_base_subscribe_odometry_message(None, seen.append, CARMEN_SUBSCRIBE_LATEST)
        assert isinstance(static, carmen_base_odometry_message)
        assert ego.wait_for_peers(PEERS_S)
        for i in range(5):
            send_odometry(ego, 100.0 + i, x=float(i), y=2.0, theta=0.5, tv=0.3, rv=-0.1)
        assert ego.wait_delivered(PEERS_S)
        until(lambda: seen, 'the odometry handler')
        assert carmen_ipc_sleep(0.2) == 0          # nothing older is handed over afterwards
        assert len(seen) == 1 and seen[0] is static
        assert (static.x, static.y, static.theta, static.tv, static.rv, static.acceleration) == (
            4.0, 2.0, 0.5, 0.3, -0.1, 0.25)
        assert static.timestamp == 104.0 and static.host == 'Robot'
        # Subscribing again without memory keeps the same static message (3.0.1).
        assert carmen_base_subscribe_odometry_message(None, seen.append, CARMEN_SUBSCRIBE_LATEST) is static


def test_all_hands_over_every_message_in_order_in_the_programs_own_memory(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        mine = carmen_base_odometry_message()
        seen: list[tuple[bool, float]] = []
        used = carmen_base_subscribe_odometry_message(mine, lambda m: seen.append((m is mine, m.x)),
                                                      CARMEN_SUBSCRIBE_ALL)
        assert used is mine
        assert ego.wait_for_peers(PEERS_S)
        for i in range(200):
            send_odometry(ego, 10.0 + i * 0.01, x=float(i))
        assert ego.wait_delivered(PEERS_S)
        until(lambda: len(seen) >= 200, '200 odometry messages')
        assert seen == [(True, float(i)) for i in range(200)]
        assert mine.x == 199.0


def test_a_null_handler_updates_the_memory_and_unsubscribe_releases_the_stream(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        mine = carmen_base_odometry_message()
        assert carmen_base_subscribe_odometry_message(mine, None, CARMEN_SUBSCRIBE_LATEST) is mine
        static = carmen_base_subscribe_bumper_message(None, None, CARMEN_SUBSCRIBE_LATEST)
        bumpers = supply(robot, Bumper('PlutoBaseBumpers'))
        assert ego.wait_for_peers(PEERS_S) and bumpers.wait_for_peers(PEERS_S)
        send_odometry(ego, 7.0, x=1.5)
        bumpers.data.bumpers = [False, True, False]
        bumpers.data.bumped = True
        bumpers.data.timestamp = Time(8.0)
        assert bumpers.publish_data()
        until(lambda: mine.x == 1.5 and static.num_sonars == 3, 'memory updated without handlers')
        assert static.range == [0.0, 1.0, 0.0] and static.num_bumpers == 3 and static.timestamp == 8.0
        assert carmen_base_subscribe_odometry_message(None, None, CARMEN_UNSUBSCRIBE) is None
        assert 'PlutoBaseMotion' not in ipc.feeds
        deadline = time.monotonic() + PEERS_S
        while ego.peers() and time.monotonic() < deadline:    # the reader left DDS
            time.sleep(0.05)
        assert ego.peers() == 0
        send_odometry(ego, 9.0, x=9.0)
        assert carmen_ipc_sleep(0.3) == 0
        assert mine.x == 1.5


def test_sonar_ir_and_lasers_in_carmens_fields_and_order(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        sonar = supply(robot, RangeFinder('PlutoBaseSonar'))
        ir = supply(robot, RangeFinder('PlutoBaseIR'))
        front = supply(robot, RangeFinder('PlutoLaser'))
        rear = supply(robot, RangeFinder('PlutoRearLaser'))
        # A uniform ring of 4 (as our bases describe theirs): the first ahead at 0.3 m.
        sonar.info.uniform.set_value(True)
        for name, value in (('x_offset', 0.3), ('y_offset', 0.0), ('theta_offset', 0.0),
                            ('theta_separation', math.pi / 2)):
            getattr(sonar.info, name).set_value(value)
        sonar.publish_info()
        got = {}
        carmen_base_subscribe_sonar_message(None, lambda m: got.setdefault('sonar', m), CARMEN_SUBSCRIBE_LATEST)
        carmen_base_subscribe_ir_message(None, lambda m: got.setdefault('ir', m), CARMEN_SUBSCRIBE_LATEST)
        carmen_laser_subscribe_frontlaser_message(None, lambda m: got.setdefault('front', m),
                                                  CARMEN_SUBSCRIBE_LATEST)
        carmen_laser_subscribe_rearlaser_message(None, lambda m: got.setdefault('rear', m),
                                                 CARMEN_SUBSCRIBE_LATEST)
        for obj in (sonar, ir, front, rear):
            assert obj.wait_for_peers(PEERS_S)
        assert sonar.wait_delivered(PEERS_S, channel='info')
        until(lambda: ipc.feeds['PlutoBaseSonar'].obj.received('info') > 0, 'the sonar info')
        for obj, values in ((sonar, [1.0, 2.0, 3.0, 4.0]), (ir, [0.1, 0.2]),
                            (front, [float(i) / 10 for i in range(181)]), (rear, [5.0] * 361)):
            obj.data.ranges = values
            obj.data.timestamp = Time(50.0)
            assert obj.publish_data()
        until(lambda: len(got) == 4, 'the four messages')
        s = got['sonar']
        assert s.num_sonars == 4 and s.range == [1.0, 2.0, 3.0, 4.0] and s.timestamp == 50.0
        expected = [(0.3, 0.0, 0.0), (0.0, 0.3, math.pi / 2), (-0.3, 0.0, math.pi), (0.0, -0.3, 1.5 * math.pi)]
        for offset, (x, y, theta) in zip(s.sonar_offsets, expected):
            assert offset.x == pytest.approx(x, abs=1e-6) and offset.y == pytest.approx(y, abs=1e-6)
            assert offset.theta == pytest.approx(theta, abs=1e-6)
        assert got['ir'].num_irs == 2 and got['ir'].range == [0.1, 0.2]
        assert got['front'].num_readings == 181 and got['front'].range[180] == 18.0
        assert got['rear'].num_readings == 361 and got['rear'].host == 'Robot'
        assert got['front'] is not got['rear']


def test_the_robots_laser_message_places_the_scan_by_the_odometry_at_its_time(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        laser = supply(robot, RangeFinder('PlutoLaser'))
        info = laser.info
        info.uniform.set_value(True)
        info.x_offset.set_value(0.2)
        info.theta_offset.set_value(-math.pi / 2)
        info.theta_separation.set_value(math.pi / 180)
        laser.publish_info()
        seen = []
        carmen_robot_subscribe_frontlaser_message(None, seen.append, CARMEN_SUBSCRIBE_ALL)
        assert ego.wait_for_peers(PEERS_S) and laser.wait_for_peers(PEERS_S)
        assert laser.wait_delivered(PEERS_S, channel='info')
        until(lambda: ipc.feeds['PlutoLaser'].obj.received('info') > 0, 'the laser info')
        # Facing north (theta pi/2), driving north at 1 m/s: y 0 at 10.0 s, 0.2 at 10.2 s.
        send_odometry(ego, 10.0, x=1.0, y=0.0, theta=math.pi / 2, tv=1.0)
        send_odometry(ego, 10.2, x=1.0, y=0.2, theta=math.pi / 2, tv=1.0)
        assert ego.wait_delivered(PEERS_S)
        until(lambda: len(ipc.odometry) == 2, 'the odometry taken in')
        laser.data.ranges = [2.0] * 181
        laser.data.timestamp = Time(10.1)
        assert laser.publish_data()
        until(lambda: seen, 'the robot laser message')
        m = seen[0]
        assert (m.odom_x, m.odom_theta) == (1.0, pytest.approx(math.pi / 2))
        assert m.odom_y == pytest.approx(0.1)
        assert (m.x, m.y, m.theta) == (pytest.approx(1.0), pytest.approx(0.3), pytest.approx(math.pi / 2))
        assert (m.tv, m.num_readings, m.timestamp) == (1.0, 181, 10.1)


class FakeNavigator:
    """A NavigatorTransport supplier that answers requests as our navigator's status does."""

    def __init__(self, robot) -> None:
        self.obj = supply(robot, NavigatorTransport('Navigator'))
        self.obj.set_auto_timestamp(True)
        self.requests: list[set[str]] = []
        self.goal = (0.0, 0.0)

    def status(self, autonomous: bool, reason: int) -> None:
        d = self.obj.data
        d.robot, d.goal = Pose(1.0, 2.0, 0.5), Point(*self.goal)
        d.goal_set, d.autonomous, d.stop_reason = True, autonomous, reason
        assert self.obj.publish_data()

    def answer(self) -> None:
        while self.obj.get_next_request():
            r = self.obj.requests
            written = set(r.ros_message().set_fields)
            self.requests.append(written)
            if 'goal' in written:
                self.goal = (r.goal.get_value().x(), r.goal.get_value().y())
            if 'autonomous' in written and not r.autonomous.get_value():
                self.status(False, 2)


def test_autonomous_stopped_comes_once_per_end_of_autonomous_motion(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        nav = FakeNavigator(robot)
        reasons: list[tuple[int, bool]] = []
        static = carmen_navigator_subscribe_autonomous_stopped_message(
            None, lambda m: reasons.append((m.reason, m is static)), CARMEN_SUBSCRIBE_ALL)
        status = carmen_navigator_subscribe_status_message(None, None, CARMEN_SUBSCRIBE_LATEST)
        planned = carmen_navigator_subscribe_plan_message(None, None, CARMEN_SUBSCRIBE_LATEST)
        assert nav.obj.wait_for_peers(PEERS_S)
        nav.status(False, 0)                    # where it stands: no event
        carmen_navigator_set_goal(4.0, 5.0)     # held until the navigator is heard
        carmen_navigator_go()
        until(lambda: set().union(*nav.requests) == {'goal', 'autonomous'}, 'set_goal and go', robot=robot,
              every=nav.answer)
        assert nav.goal == (4.0, 5.0)
        nav.status(True, 0)
        nav.status(False, 1)                    # goal reached
        nav.status(False, 1)                    # the periodic status again: no event
        until(lambda: reasons, 'goal reached', robot=robot)
        carmen_navigator_stop()                 # standing at the goal: user stopped
        until(lambda: len(reasons) == 2, 'the first stop', robot=robot, every=nav.answer)
        carmen_navigator_stop()                 # a stop again: the status does not change, still an event
        until(lambda: len(reasons) == 3, 'the second stop', robot=robot, every=nav.answer)
        nav.status(True, 0)
        nav.status(False, 3)                    # not reached
        until(lambda: len(reasons) == 4, 'not reached', robot=robot)
        assert carmen_ipc_sleep(0.3) == 0
        assert reasons == [(CARMEN_NAVIGATOR_GOAL_REACHED_v, True), (CARMEN_NAVIGATOR_USER_STOPPED_v, True),
                           (CARMEN_NAVIGATOR_USER_STOPPED_v, True), (CARMEN_NAVIGATOR_UNKNOWN_v, True)]
        assert (status.autonomous, status.goal_set, status.goal.x, status.robot.theta) == (0, 1, 4.0, 0.5)
        assert planned.timestamp == status.timestamp > 0 and planned.path_length == 0
        first, second = carmen_navigator_query_status(), carmen_navigator_query_status()
        assert first is not second and first == second    # new memory each time (3.0.2)
        assert (first.autonomous, first.goal_set, first.goal.x, first.goal.y) == (0, 1, 4.0, 5.0)
        assert (first.robot.x, first.robot.y, first.robot.theta) == (1.0, 2.0, 0.5)
        plan = carmen_navigator_query_plan()
        assert plan is not None and plan.path_length == 0 and plan.path == []


def test_timers_run_while_messages_are_handled(ros_domain: int) -> None:
    with carmen_and_robot():
        calls: list[tuple[str, int, int]] = []
        carmen_ipc_addPeriodicTimer(0.1, lambda data, now, due: calls.append((data, now, due)), 'mine')
        start = time.monotonic()
        assert carmen_ipc_sleep(1.0) == 0
        assert time.monotonic() - start >= 1.0
        assert len(calls) >= 3 and all(data == 'mine' and now >= due for data, now, due in calls)
        dues = [due for _, _, due in calls]
        assert all(b > a for a, b in zip(dues, dues[1:]))


def test_bad_calls_are_refused_with_the_reason(ros_domain: int) -> None:
    with pytest.raises(NotRegisteredError, match='carmen_ipc_initialize'):
        carmen_base_subscribe_odometry_message(None, None, CARMEN_SUBSCRIBE_LATEST)
    with carmen_and_robot() as (ipc, _):
        with pytest.raises(InvalidValueError, match='subscribe_how 7: one of CARMEN_UNSUBSCRIBE'):
            carmen_base_subscribe_odometry_message(None, None, 7)
        assert ipc.feeds == {}
        with pytest.raises(TypeError, match='msg must be a carmen_base_odometry_message'):
            carmen_base_subscribe_odometry_message(object(), None, CARMEN_SUBSCRIBE_LATEST)
        with pytest.raises(TypeError, match='handler must be callable'):
            carmen_base_subscribe_odometry_message(None, 3, CARMEN_SUBSCRIBE_LATEST)
        with pytest.raises(InvalidValueError, match='finite'):
            carmen_robot_velocity_command(math.nan, 0.0)
        with pytest.raises(InvalidValueError, match='finite'):
            carmen_navigator_set_goal(math.inf, 1.0)
        with pytest.raises(InvalidValueError, match='a time >= 0'):
            carmen_ipc_sleep(-1.0)


def test_dispatch_hands_over_until_a_handler_disconnects(ros_domain: int) -> None:
    with carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        seen: list[float] = []
        status = carmen_navigator_subscribe_status_message(None, None, CARMEN_SUBSCRIBE_LATEST)

        def tick(count: list[int], now: int, due: int) -> None:
            robot.step()
            count[0] += 1
            send_odometry(ego, 20.0 + count[0], x=float(count[0]))
            if len(seen) >= 3:
                carmen_ipc_disconnect()
        carmen_base_subscribe_odometry_message(None, lambda m: seen.append(m.x), CARMEN_SUBSCRIBE_ALL)
        assert ego.wait_for_peers(PEERS_S)
        carmen_ipc_addPeriodicTimer(0.05, tick, [0])
        carmen_ipc_dispatch()
        assert ipc.closed and len(seen) >= 3 and seen == sorted(seen)
        assert status.timestamp == 0.0              # no navigator: the memory was never filled
        with pytest.raises(NotRegisteredError):
            carmen_ipc_sleep(0.1)


WAITER = ('import sys\nfrom pluto_motion.carmen import *\n'
          'carmen_ipc_initialize(sys.argv)\n'
          'carmen_base_subscribe_odometry_message(None, None, CARMEN_SUBSCRIBE_LATEST)\n'
          'print("dispatching", flush=True)\ncarmen_ipc_dispatch()\n'
          'print("dispatch returned", flush=True)\ncarmen_ipc_disconnect()\n')


def test_a_carmen_program_quits_cleanly_on_sigint(ros_domain: int, tmp_path) -> None:
    script = tmp_path / 'carmen_wait.py'
    script.write_text(WAITER)
    with ChildProcess([str(script), '-n', 'carmenWait']) as child:
        child.expect('dispatching', timeout=60)
        child.process.send_signal(signal.SIGINT)
        child.expect('dispatch returned', timeout=30)
        assert child.process.wait(timeout=30) == 0, child.stderr


def test_a_registration_run_reports_the_subscribed_streams_and_ends(ros_domain: int, tmp_path) -> None:
    """The MCP runs every module once with -r to learn its streams: the program must not go on."""
    script = tmp_path / 'carmen_wait.py'
    script.write_text(WAITER)
    with ChildProcess([str(script), '-n', 'carmenWait', '-r']) as child:
        child.expect('consumes Egomotion PlutoBaseMotion', timeout=60)
        assert child.process.wait(timeout=60) == 0, child.stderr
        assert 'dispatch returned' not in child.stdout
