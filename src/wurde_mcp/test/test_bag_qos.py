"""rosbag2's ``offered_qos_profiles`` as ``record`` writes them (read back by an independent reader,
rosbags) and as ``replay`` reads them (rosbag2's metadata versions 4-8 and 9), the QoS a replay
offers (``ros2 bag play``'s rule), and the message type names of bags."""

from __future__ import annotations

import pytest
import yaml
from rclpy.duration import Duration
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile, ReliabilityPolicy,
                       qos_profile_sensor_data)
from rosbags.interfaces import QosDurability, QosHistory, QosLiveliness, QosReliability
from rosbags.rosbag2.metadata import parse_qos
from wurde_mcp.recording.errors import MessageTypeError
from wurde_mcp.recording.message_types import message_class
from wurde_mcp.recording.qos import Offer, offered_profile, offered_qos_yaml, offers_from_yaml, replay_qos

# A channel's offered_qos_profiles of rosbag2's own test bag ``talker`` (metadata version 4, rmw's numbers).
TALKER_ROSOUT = ('- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n  deadline:\n    sec: 0\n'
                 '    nsec: 0\n  lifespan:\n    sec: 10\n    nsec: 0\n  liveliness: 1\n'
                 '  liveliness_lease_duration:\n    sec: 0\n    nsec: 0\n  avoid_ros_namespace_conventions: false')


def test_an_offered_profile_is_read_back_alike_by_rosbags() -> None:
    latched = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL, lifespan=Duration(seconds=10, nanoseconds=5),
                         deadline=Duration(nanoseconds=2**63 - 1),      # as discovery reports "none"
                         liveliness=LivelinessPolicy.AUTOMATIC)
    text = offered_qos_yaml([offered_profile(latched), offered_profile(qos_profile_sensor_data)])
    assert yaml.safe_load(text)[0]['durability'] == 'transient_local'       # names, version 9
    first, second = parse_qos(text)
    assert (first.history, first.depth, first.reliability, first.durability, first.liveliness) == (
        QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL, QosLiveliness.AUTOMATIC)
    assert (first.lifespan.sec, first.lifespan.nsec) == (10, 5)
    assert (first.deadline.sec, first.deadline.nsec) == (9223372036, 854775807)     # rmw's infinite
    assert (second.reliability, second.durability, second.depth) == (QosReliability.BEST_EFFORT,
                                                                      QosDurability.VOLATILE, 5)


def test_offers_are_read_in_every_version_and_replayed_as_ros2_bag_play_does() -> None:
    assert offers_from_yaml(TALKER_ROSOUT) == (Offer('reliable', 'transient_local'),)
    assert offers_from_yaml([{'reliability': 'best_effort', 'durability': 'volatile'}]) == \
        (Offer('best_effort', 'volatile'),)
    assert offers_from_yaml('') == offers_from_yaml(None) == ()
    with pytest.raises(ValueError, match='reliability and durability'):
        offers_from_yaml('- history: 1\n')
    latched = replay_qos(offers_from_yaml(TALKER_ROSOUT))
    assert (latched.reliability, latched.durability) == (ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL)
    sensor = replay_qos([Offer('best_effort', 'volatile')] * 2)
    assert (sensor.reliability, sensor.durability) == (ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE)
    mixed = replay_qos([Offer('reliable', 'transient_local'), Offer('best_effort', 'volatile')])
    assert (mixed.reliability, mixed.durability) == (ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE)
    old = replay_qos((), {'durability': 'transient_local', 'reliability': 'best_effort'})
    assert (old.reliability, old.durability) == (ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.TRANSIENT_LOCAL)
    preferred = replay_qos([Offer('reliable', 'volatile')], {'durability': 'transient_local'})
    assert preferred.durability == DurabilityPolicy.VOLATILE               # rosbag2's offers come first


def test_type_names_of_bags_find_their_classes_or_say_why_not() -> None:
    from rcl_interfaces.srv import GetParameters
    from std_msgs.msg import String
    assert message_class('std_msgs/String') is message_class('std_msgs/msg/String') is String
    assert message_class('rcl_interfaces/srv/GetParameters_Event') is GetParameters.Event
    with pytest.raises(MessageTypeError, match="test_msgs/msg/Basic is not installed here .*test_msgs"):
        message_class('test_msgs/msg/Basic')
    for bad in ('os.path/msg/join', 'std_msgs', 'std_msgs/lib/String', 'std_msgs/msg/Nothing'):
        with pytest.raises(MessageTypeError):
            message_class(bad)
