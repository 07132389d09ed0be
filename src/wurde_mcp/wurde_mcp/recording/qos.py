"""A topic's QoS as rosbag2 keeps it (``offered_qos_profiles``), and the QoS a replay offers.

rosbag2 stores, per topic, the profile each publisher offered when the recording began
(``rosbag2_storage/qos.cpp``): history, depth, reliability, durability, deadline, lifespan,
liveliness, liveliness lease duration and ``avoid_ros_namespace_conventions``.  Metadata version 9
(Jazzy) names the policies (``reliable``, ``transient_local``, ...) and, in ``metadata.yaml``, holds
the list as YAML; an MCAP channel holds it as a YAML string in its ``offered_qos_profiles``
metadata.  Versions 4-8 wrote the policies as rmw's numbers, always as a string.  Both are read.

``ros2 bag play`` offers what every recorded publisher offered when they agree (so ``/tf_static``
and ``/map`` come back transient local), else rosbag2's default (reliable, volatile):
:func:`replay_qos` does the same for reliability and durability.  Files recorded by this suite
before it wrote ``offered_qos_profiles`` carry ``durability`` and ``reliability`` channel metadata
instead, which is used when there are no offers.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import yaml
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

__all__ = ['REPLAY_DEPTH', 'Offer', 'offered_profile', 'offered_qos_yaml', 'offers_from_yaml', 'replay_qos']

#: The depth of a replay's publishers (a burst of recorded messages is kept whole).
REPLAY_DEPTH = 1000
_NS = 1_000_000_000


@dataclasses.dataclass(frozen=True)
class Offer:
    """What one recorded publisher offered, by rmw's names (``reliable``, ``best_effort``,
    ``transient_local``, ``volatile``, ``system_default``, ``unknown``, ...)."""

    reliability: str
    durability: str


def _duration(duration: Duration) -> dict[str, int]:
    """rmw_time_t as rosbag2 writes it; rmw's infinite is (9223372036, 854775807)."""
    return {'sec': duration.nanoseconds // _NS, 'nsec': duration.nanoseconds % _NS}


def offered_profile(profile: QoSProfile) -> dict[str, Any]:
    """One publisher's profile in rosbag2's metadata version 9 form.

    :param profile: the QoS the publisher offers (from the ROS graph).
    """
    return {'history': profile.history.name.lower(), 'depth': int(profile.depth),
            'reliability': profile.reliability.name.lower(), 'durability': profile.durability.name.lower(),
            'deadline': _duration(profile.deadline), 'lifespan': _duration(profile.lifespan),
            'liveliness': profile.liveliness.name.lower(),
            'liveliness_lease_duration': _duration(profile.liveliness_lease_duration),
            'avoid_ros_namespace_conventions': bool(profile.avoid_ros_namespace_conventions)}


def offered_qos_yaml(profiles: Sequence[Mapping[str, Any]]) -> str:
    """The ``offered_qos_profiles`` string of an MCAP channel (YAML, as rosbag2's
    ``serialize_rclcpp_qos_vector`` writes it).

    :param profiles: one profile per publisher, as :func:`offered_profile` makes them.
    """
    return yaml.safe_dump([dict(p) for p in profiles], default_flow_style=False, sort_keys=False).strip()


def _policy(value: Any, numbers: type[ReliabilityPolicy] | type[DurabilityPolicy]) -> str:
    """A policy written by name (version 9) or by rmw's number (versions 4-8)."""
    if isinstance(value, bool):
        raise ValueError(f'{value!r} is not a QoS policy')
    if isinstance(value, int):
        try:
            return numbers(value).name.lower()
        except ValueError:
            return 'unknown'
    if isinstance(value, str):
        return value.strip().lower()
    raise ValueError(f'{value!r} is not a QoS policy')


def offers_from_yaml(value: str | Sequence[Any] | None) -> tuple[Offer, ...]:
    """The offers of ``offered_qos_profiles`` as found: a YAML string (an MCAP channel's, or a
    metadata.yaml of version 4-8), a list (metadata.yaml version 9), or nothing.

    :param value: the value found; None or '' gives no offers.
    :returns: one offer per profile, policies by rmw's lower-case names (a number of versions
        4-8 is named; an unknown number is ``unknown``).
    :raises ValueError: not a list of profiles with a reliability and a durability each.
    """
    if value is None or value == '':
        return ()
    profiles = yaml.safe_load(value) if isinstance(value, str) else value
    if profiles is None:
        return ()
    if not isinstance(profiles, list):
        raise ValueError('offered_qos_profiles is not a list of profiles')
    offers = []
    for profile in profiles:
        if not isinstance(profile, Mapping) or 'reliability' not in profile or 'durability' not in profile:
            raise ValueError(f'a profile without reliability and durability: {profile!r}')
        offers.append(Offer(_policy(profile['reliability'], ReliabilityPolicy),
                            _policy(profile['durability'], DurabilityPolicy)))
    return tuple(offers)


def replay_qos(offers: Iterable[Offer], legacy: Mapping[str, str] | None = None) -> QoSProfile:
    """The profile to replay a topic with: the recorded publishers' reliability and durability
    when they all agree, rosbag2's default (reliable, volatile) when they differ; without offers,
    the ``durability`` and ``reliability`` metadata of files recorded before (default the same).

    :param offers: the recorded publishers' offers (:func:`offers_from_yaml`).
    :param legacy: a channel's ``reliability`` and ``durability`` metadata, used only without
        offers (None: none).
    :returns: a profile of depth :data:`REPLAY_DEPTH`.
    """
    offers = set(offers)
    if len(offers) == 1:
        (offer,) = offers
        reliability, durability = offer.reliability, offer.durability
    elif not offers and legacy:
        reliability, durability = legacy.get('reliability', ''), legacy.get('durability', '')
    else:
        reliability = durability = ''
    return QoSProfile(depth=REPLAY_DEPTH,
                      reliability=ReliabilityPolicy.BEST_EFFORT if reliability == 'best_effort'
                      else ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if durability == 'transient_local'
                      else DurabilityPolicy.VOLATILE)
