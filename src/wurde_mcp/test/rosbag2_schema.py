"""rosbag2's metadata schema for Jazzy (metadata version 9), checked the way rosbag2 reads it.

From ros2/rosbag2, jazzy branch: ``rosbag2_storage/include/rosbag2_storage/yaml.hpp`` (what
``convert<BagMetadata>::decode`` reads: every key below; ``files`` from version 5,
``custom_data`` from 6, ``type_description_hash`` from 7, ``ros_distro`` from 8; from version 9
``offered_qos_profiles`` is a YAML sequence, not a string) and
``rosbag2_storage/src/rosbag2_storage/qos.cpp`` (a profile: the policies by rmw's names, the
durations as ``sec``/``nsec``, ``avoid_ros_namespace_conventions``).
"""

from __future__ import annotations

from typing import Any

HISTORY = {'system_default', 'keep_last', 'keep_all', 'unknown'}
RELIABILITY = {'system_default', 'reliable', 'best_effort', 'unknown', 'best_available'}
DURABILITY = {'system_default', 'transient_local', 'volatile', 'unknown', 'best_available'}
LIVELINESS = {'system_default', 'automatic', 'manual_by_topic', 'unknown', 'best_available'}


def _is(value: Any, kind: type) -> bool:
    return isinstance(value, kind) and not (kind is int and isinstance(value, bool))


def _unsigned(value: Any, where: str) -> None:
    assert _is(value, int) and value >= 0, f'{where}: {value!r} is not an unsigned integer'


def _duration(value: Any, where: str) -> None:
    assert isinstance(value, dict) and set(value) == {'sec', 'nsec'}, f'{where}: {value!r}'
    _unsigned(value['sec'], f'{where}.sec')
    _unsigned(value['nsec'], f'{where}.nsec')


def check_profile(profile: Any, where: str) -> None:
    """One offered QoS profile, version 9."""
    assert isinstance(profile, dict), f'{where}: not a mapping'
    assert set(profile) == {'history', 'depth', 'reliability', 'durability', 'deadline', 'lifespan', 'liveliness',
                            'liveliness_lease_duration', 'avoid_ros_namespace_conventions'}, f'{where}: {set(profile)}'
    assert profile['history'] in HISTORY, where
    _unsigned(profile['depth'], f'{where}.depth')
    assert profile['reliability'] in RELIABILITY and profile['durability'] in DURABILITY, where
    assert profile['liveliness'] in LIVELINESS, where
    for key in ('deadline', 'lifespan', 'liveliness_lease_duration'):
        _duration(profile[key], f'{where}.{key}')
    assert isinstance(profile['avoid_ros_namespace_conventions'], bool), where


def check_bagfile_information(info: Any) -> None:
    """The mapping under ``rosbag2_bagfile_information`` (or an MCAP file's
    ``serialized_metadata``), as rosbag2 Jazzy decodes a version 9 bag."""
    assert isinstance(info, dict)
    assert set(info) == {'version', 'storage_identifier', 'duration', 'starting_time', 'message_count',
                         'topics_with_message_count', 'compression_format', 'compression_mode',
                         'relative_file_paths', 'files', 'custom_data', 'ros_distro'}, set(info)
    assert info['version'] == 9 and info['storage_identifier'] in ('mcap', 'sqlite3')
    assert set(info['duration']) == {'nanoseconds'} and set(info['starting_time']) == {'nanoseconds_since_epoch'}
    _unsigned(info['duration']['nanoseconds'], 'duration')
    _unsigned(info['starting_time']['nanoseconds_since_epoch'], 'starting_time')
    _unsigned(info['message_count'], 'message_count')
    assert _is(info['compression_format'], str) and _is(info['compression_mode'], str)
    assert info['custom_data'] is None or isinstance(info['custom_data'], dict)
    assert _is(info['ros_distro'], str) and info['ros_distro']
    assert isinstance(info['relative_file_paths'], list) and all(_is(p, str) for p in info['relative_file_paths'])
    assert isinstance(info['files'], list)
    for k, entry in enumerate(info['files']):
        assert set(entry) == {'path', 'starting_time', 'duration', 'message_count'}, f'files[{k}]'
        assert _is(entry['path'], str)
        _unsigned(entry['starting_time']['nanoseconds_since_epoch'], f'files[{k}].starting_time')
        _unsigned(entry['duration']['nanoseconds'], f'files[{k}].duration')
        _unsigned(entry['message_count'], f'files[{k}].message_count')
    assert isinstance(info['topics_with_message_count'], list)
    for k, entry in enumerate(info['topics_with_message_count']):
        where = f'topics_with_message_count[{k}]'
        assert set(entry) == {'topic_metadata', 'message_count'}, where
        _unsigned(entry['message_count'], f'{where}.message_count')
        meta = entry['topic_metadata']
        assert set(meta) == {'name', 'type', 'serialization_format', 'offered_qos_profiles',
                             'type_description_hash'}, where
        assert all(_is(meta[key], str) for key in ('name', 'type', 'serialization_format', 'type_description_hash'))
        assert isinstance(meta['offered_qos_profiles'], list), f'{where}: version 9 keeps the profiles as a sequence'
        for j, profile in enumerate(meta['offered_qos_profiles']):
            check_profile(profile, f'{where}.offered_qos_profiles[{j}]')
