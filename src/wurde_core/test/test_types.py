"""Time, the geometry types, the enums and the stream-name rule."""

from __future__ import annotations

import datetime

import pytest

from wurde_core import (ConnectionStrategy, Point, Point3D, Pose, Pose3D, PVector, RunState,
                        Time, WurdeError, stream_name, topic)


def test_time_keeps_microseconds_and_compares_with_everything() -> None:
    t = Time(1700000000.123456)
    assert t.get_microseconds() == 1700000000123456
    assert t.get_seconds() == pytest.approx(1700000000.123456, abs=1e-6)
    assert t == Time(microseconds=1700000000123456)
    assert t > 1700000000 and t < 1700000001
    assert t == datetime.datetime.fromtimestamp(1700000000.123456, tz=datetime.timezone.utc)
    later = Time(1700000000.123457)
    assert later > t and later >= t and t <= later and t != later
    assert later - t == pytest.approx(1e-6)
    from builtin_interfaces.msg import Time as Stamp
    stamp = t.to_msg(Stamp())
    assert (stamp.sec, stamp.nanosec) == (1700000000, 123456000)
    assert Time.from_msg(stamp) == t
    assert Time.now() > t


def test_point_and_pose_constructors_and_accessors() -> None:
    p = Point()
    assert (p.x(), p.y(), p.value()) == (0.0, 0.0, 0.0)
    p = Point(1, 2, 0.5)
    assert (p.x(), p.y(), p.value()) == (1.0, 2.0, 0.5)
    p.x(3.5)
    assert p.x() == 3.5
    q = Point3D(1, 2, 3)
    assert (q.x(), q.y(), q.z(), q.value()) == (1.0, 2.0, 3.0, 0.0)
    assert Point3D(1, 2, 3, 4).value() == 4.0
    pose = Pose(1, 2, 0.5, 0.25)
    assert (pose.x(), pose.y(), pose.theta(), pose.value()) == (1.0, 2.0, 0.5, 0.25)
    assert Pose(1, 2).theta() == 0.0
    p3 = Pose3D(1, 2, 3, 0.1, 0.2, 0.3)
    assert (p3.theta(), p3.phi(), p3.psi(), p3.value()) == (0.1, 0.2, 0.3, 0.0)
    p3.psi(-0.3)
    assert p3.psi() == -0.3
    assert Pose3D(1, 2, 3).z() == 3.0
    with pytest.raises(TypeError):
        Pose3D(1, 2)
    with pytest.raises(TypeError):
        Point3D(1, 2)
    assert Pose(1, 2, 3) == Pose(1, 2, 3) and Pose(1, 2, 3) != Pose(1, 2, 4)
    assert PVector(2.0, 0.5).magnitude() == 2.0


def test_geometry_views_write_through_to_their_message() -> None:
    from wurde_interfaces.msg import Pose as PoseMsg
    message = PoseMsg()
    view = Pose.wrap(message)
    view.x(4.0)
    assert message.x == 4.0


def test_enums_match_the_seed_names() -> None:
    assert [s.name for s in RunState] == ['RUN', 'IDLE', 'RESET', 'RESTART', 'QUIT']
    from wurde_core.enums import ENUMS
    from wurde_idl.types import BUILTIN_ENUMS
    assert {name: tuple(m.name for m in e) for name, e in ENUMS.items()} == BUILTIN_ENUMS   # the messages' table
    assert all([m.value for m in e] == list(range(len(e))) for e in ENUMS.values())
    assert {s.name for s in ConnectionStrategy} == {'NORMAL', 'ASSIGNED', 'AUTO'}
    from wurde_interfaces.msg import RunState as RunStateMsg
    assert RunState.QUIT == RunStateMsg.QUIT


@pytest.mark.parametrize('stream, expected', [
    ('Bar', '/wurde/Bar/data'),
    ('Laser_Pose', '/wurde/Laser_Pose/data'),
    ('Localization/Dead-Reckoning', '/wurde/Localization/w__Dead_2DReckoning/data'),
    ('Localization/Laser_Dead-Reckoning', '/wurde/Localization/w__Laser_5FDead_2DReckoning/data'),
    ('3d', '/wurde/w__3d/data'),
    ('a__b', '/wurde/w__a_5F_5Fb/data'),
    ('Café', '/wurde/w__Caf_C3_A9/data'),
    ('heartbeat/FooServer', '/wurde/heartbeat/FooServer/data'),
])
def test_stream_names_map_to_valid_topics_and_back(stream: str, expected: str) -> None:
    from rclpy.validate_full_topic_name import validate_full_topic_name
    name = topic(stream, 'data')
    assert name == expected
    validate_full_topic_name(name)
    assert stream_name(name) == (stream, 'data')
    in_robot1 = topic(stream, 'data', '/robot1')           # a module in a namespace
    assert in_robot1 == '/robot1' + expected
    assert stream_name(in_robot1, '/robot1/') == (stream, 'data')
    with pytest.raises(WurdeError):
        stream_name(in_robot1)                              # not a stream of the root namespace


def test_bad_stream_names_are_refused() -> None:
    for bad in ('', '/a', 'a//b', 'a/'):
        with pytest.raises(WurdeError, match='empty'):
            topic(bad, 'data')
    with pytest.raises(WurdeError):
        stream_name('/other/a/data')
