"""Bags written by an independent rosbag2 writer (rosbags), for ``replay``'s tests, in the layouts
``ros2 bag record`` makes: a bag directory with ``metadata.yaml`` in MCAP or sqlite3 storage, zstd
file or message compression, split in two files as rosbag2 splits them (rosbags does not split:
two bags joined by hand under one ``metadata.yaml``), and serialization formats other than CDR.

Every bag holds the same :data:`CHATTER` on ``/chatter`` (``std_msgs/msg/String``, offered reliable
and volatile), one message on ``/latched`` (offered transient local, as ``/tf_static``), and
:data:`BASIC_COUNT` on ``/basic`` of ``test_msgs/msg/Basic``, a type registered with rosbags'
typesys only: it is not installed here, as rosbag2's own test bags' ``test_msgs`` types are not.
"""

from __future__ import annotations

import pathlib
import shutil
from typing import Any

import numpy as np
import yaml
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

STRING, BASIC = 'std_msgs/msg/String', 'test_msgs/msg/Basic'
CHATTER = [f'hello {i}' for i in range(20)]
LATCHED = 'the mounting'
BASIC_COUNT = 5
T0 = 1_700_000_000_000_000_000
STEP = 10_000_000                     # 10 ms between messages
_INFINITE = QosTime(9223372036, 854775807)


def typestore() -> Typestore:
    """Jazzy's standard types and the uninstalled ``test_msgs/msg/Basic``."""
    store = get_typestore(Stores.ROS2_JAZZY)
    store.register(get_types_from_msg('int32 number\nstring text\nfloat64[] values\n', BASIC))
    return store


def qos(durability: QosDurability) -> Qos:
    """A recorded publisher's offer as rosbag2 keeps it."""
    return Qos(QosHistory.KEEP_LAST, 10, QosReliability.RELIABLE, durability, _INFINITE, _INFINITE,
               QosLiveliness.AUTOMATIC, _INFINITE, False)


def items() -> list[tuple[str, str, int, Any]]:
    """``(topic, type, time ns, message)`` of every bag, in time order."""
    store = typestore()
    string, basic = store.types[STRING], store.types[BASIC]
    rows = [('/latched', STRING, T0, string(data=LATCHED))]
    rows += [('/chatter', STRING, T0 + (i + 1) * STEP, string(data=text)) for i, text in enumerate(CHATTER)]
    rows += [('/basic', BASIC, T0 + i * STEP + STEP // 2, basic(number=i, text='b', values=np.full(i, 0.5)))
             for i in range(BASIC_COUNT)]
    return sorted(rows, key=lambda row: row[2])


def write(path: pathlib.Path, rows: list[tuple[str, str, int, Any]], *, storage: str = 'mcap',
          compression: str = '', formats: dict[str, str] | None = None) -> pathlib.Path:
    """A bag directory by rosbags' writer (metadata version 9).  ``compression``: ``file`` or
    ``message`` (zstd); ``formats``: topic -> a serialization format other than CDR."""
    store = typestore()
    writer = Writer(path, version=9,
                    storage_plugin=StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3)
    if compression:
        writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
    with writer:
        connections = {}
        for topic, type_name, _, _ in rows:
            if topic not in connections:
                durability = QosDurability.TRANSIENT_LOCAL if topic == '/latched' else QosDurability.VOLATILE
                connections[topic] = writer.add_connection(
                    topic, type_name, typestore=store, serialization_format=(formats or {}).get(topic, 'cdr'),
                    offered_qos_profiles=[qos(durability)])
        for topic, type_name, stamp, message in rows:
            writer.write(connections[topic], stamp, bytes(store.serialize_cdr(message, type_name)))
    return path


def write_split(path: pathlib.Path, rows: list[tuple[str, str, int, Any]], *, storage: str = 'mcap') -> pathlib.Path:
    """A bag split in two files, as rosbag2 splits: ``NAME_0`` holds the first half of the time,
    ``NAME_1`` the rest, one ``metadata.yaml`` names both in order."""
    half = rows[len(rows) // 2][2]
    parts = [write(path.with_name(f'{path.name}-part{k}'), part, storage=storage)
             for k, part in enumerate(([r for r in rows if r[2] < half], [r for r in rows if r[2] >= half]))]
    path.mkdir()
    suffix = '.mcap' if storage == 'mcap' else '.db3'
    infos = [yaml.safe_load((p / 'metadata.yaml').read_text())['rosbag2_bagfile_information'] for p in parts]
    names = [f'{path.name}_{k}{suffix}' for k in range(len(parts))]
    for part, info, name in zip(parts, infos, names, strict=True):
        shutil.move(part / info['relative_file_paths'][0], path / name)
        shutil.rmtree(part)
    info = infos[0]
    info['relative_file_paths'] = names
    info['files'] = [{**part['files'][0], 'path': name} for part, name in zip(infos, names, strict=True)]
    info['message_count'] = sum(part['message_count'] for part in infos)
    end = max(p['starting_time']['nanoseconds_since_epoch'] + p['duration']['nanoseconds'] for p in infos)
    info['duration']['nanoseconds'] = end - info['starting_time']['nanoseconds_since_epoch']
    counts: dict[str, int] = {}
    for part in infos:
        for entry in part['topics_with_message_count']:
            counts[entry['topic_metadata']['name']] = counts.get(entry['topic_metadata']['name'], 0) \
                + entry['message_count']
    info['topics_with_message_count'] = [
        {**entry, 'message_count': counts[entry['topic_metadata']['name']]}
        for entry in {e['topic_metadata']['name']: e for p in infos for e in p['topics_with_message_count']}.values()]
    (path / 'metadata.yaml').write_text(yaml.safe_dump({'rosbag2_bagfile_information': info}))
    return path
