"""rosbag2's ``metadata.yaml``: written for a bag directory ``record`` makes, read for ``replay``.

The layout written is rosbag2's (Jazzy, ``rosbag2_storage/yaml.hpp``), metadata version 9, so
``ros2 bag`` and rosbags read the directories ``record`` writes; docs/wurde-mcp.md ("rosbag2's
metadata.yaml") shows it.  Reading takes every version rosbag2 wrote (1-9: ``compression_*``
from 3, ``files`` from 5, the type hash from 7; ``offered_qos_profiles`` a YAML string before 9),
and only what ``replay`` needs.

Before changing it: check a change against rosbag2's ``yaml.hpp`` (the tests compare the schema);
errors name the file and the key; the file is written whole, through a temporary file beside it,
so a recorder that dies leaves the old file or none.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
from collections.abc import Mapping, Sequence
from typing import Any

import yaml

from .errors import BagError

__all__ = ['METADATA_FILE', 'METADATA_VERSION', 'NO_TIME', 'BagMetadata', 'FileEntry', 'TopicEntry',
           'bagfile_information', 'read_metadata', 'write_metadata']

METADATA_FILE = 'metadata.yaml'
METADATA_VERSION = 9
#: rosbag2's starting time of a bag or file without messages (time_point::max()).
NO_TIME = 2**63 - 1
ROOT = 'rosbag2_bagfile_information'


@dataclasses.dataclass(frozen=True)
class TopicEntry:
    """One ``topics_with_message_count`` entry.  ``offered_qos_profiles``: a list of profiles
    (:func:`.qos.offered_profile`) when writing; as found (a list or a YAML string) when read."""

    name: str
    type: str
    serialization_format: str
    offered_qos_profiles: Any
    type_description_hash: str
    message_count: int


@dataclasses.dataclass(frozen=True)
class FileEntry:
    """One storage file of the bag (``files``); ``starting_time`` is :data:`NO_TIME` when empty."""

    path: str
    starting_time: int
    duration: int
    message_count: int


@dataclasses.dataclass(frozen=True)
class BagMetadata:
    """What ``replay`` needs of a ``metadata.yaml``."""

    path: pathlib.Path
    version: int
    storage_identifier: str
    relative_file_paths: tuple[str, ...]
    compression_format: str
    compression_mode: str
    topics: tuple[TopicEntry, ...]


def bagfile_information(*, storage_identifier: str, files: Sequence[FileEntry], topics: Sequence[TopicEntry],
                        ros_distro: str = '') -> dict[str, Any]:
    """The whole ``metadata.yaml`` document of a bag made of ``files`` (in order), version 9.

    :param storage_identifier: the storage plugin's name (``mcap``).
    :param files: the bag's storage files, in split order; the bag's start and duration span
        those with messages.
    :param topics: the topics, with their offered QoS profiles as a list.
    :param ros_distro: the distribution named ('': ``ROS_DISTRO``, else ``jazzy``).
    """
    filled = [f for f in files if f.message_count]
    start = min((f.starting_time for f in filled), default=NO_TIME)
    end = max((f.starting_time + f.duration for f in filled), default=NO_TIME)
    information = {
        'version': METADATA_VERSION,
        'storage_identifier': storage_identifier,
        'duration': {'nanoseconds': end - start},
        'starting_time': {'nanoseconds_since_epoch': start},
        'message_count': sum(f.message_count for f in files),
        'topics_with_message_count': [
            {'topic_metadata': {'name': t.name, 'type': t.type, 'serialization_format': t.serialization_format,
                                'offered_qos_profiles': list(t.offered_qos_profiles),
                                'type_description_hash': t.type_description_hash},
             'message_count': t.message_count} for t in topics],
        'compression_format': '',
        'compression_mode': '',
        'relative_file_paths': [f.path for f in files],
        'files': [{'path': f.path, 'starting_time': {'nanoseconds_since_epoch': f.starting_time},
                   'duration': {'nanoseconds': f.duration}, 'message_count': f.message_count} for f in files],
        'custom_data': None,
        'ros_distro': ros_distro or os.environ.get('ROS_DISTRO') or 'jazzy',
    }
    return {ROOT: information}


def dump(document: Mapping[str, Any]) -> str:
    """YAML text of a metadata document (key order kept, block style, as yaml-cpp writes).

    :param document: a document from :func:`bagfile_information`.
    """
    return yaml.safe_dump(dict(document), default_flow_style=False, sort_keys=False)


def write_metadata(directory: pathlib.Path, document: Mapping[str, Any]) -> pathlib.Path:
    """Write ``metadata.yaml`` into ``directory`` whole (through a temporary file beside it).

    :param directory: the bag directory.
    :param document: a document from :func:`bagfile_information`.
    :returns: the path written.
    :raises OSError: it cannot be written.
    """
    path = directory / METADATA_FILE
    temporary = path.with_name(f'.{METADATA_FILE}.tmp')
    temporary.write_text(dump(document))
    os.replace(temporary, path)
    return path


def _get(mapping: Mapping[str, Any], key: str, kind: type | tuple[type, ...], where: str) -> Any:
    if key not in mapping:
        raise BagError(f'{where}: no {key!r}')
    value = mapping[key]
    if not isinstance(value, kind) or isinstance(value, bool) and kind is int:
        raise BagError(f'{where}: {key!r} is {value!r}, not of the expected kind')
    return value


def _topic(entry: Any, where: str) -> TopicEntry:
    if not isinstance(entry, Mapping):
        raise BagError(f'{where}: not a mapping')
    meta = _get(entry, 'topic_metadata', Mapping, where)
    inner = f'{where}.topic_metadata'
    name = _get(meta, 'name', str, inner)
    return TopicEntry(name=name, type=_get(meta, 'type', str, f'{inner} ({name})'),
                      serialization_format=_get(meta, 'serialization_format', str, f'{inner} ({name})'),
                      offered_qos_profiles=meta.get('offered_qos_profiles'),
                      type_description_hash=str(meta.get('type_description_hash') or ''),
                      message_count=int(_get(entry, 'message_count', int, f'{where} ({name})')))


def read_metadata(directory: pathlib.Path) -> BagMetadata:
    """The ``metadata.yaml`` of the bag ``directory``.

    :param directory: the bag directory.
    :raises BagError: unreadable, not YAML, or a key missing or of the wrong kind (named).
    """
    path = directory / METADATA_FILE
    try:
        document = yaml.safe_load(path.read_text())
    except OSError as error:
        raise BagError(f'{path}: cannot be read: {error.strerror or error}') from error
    except (yaml.YAMLError, UnicodeDecodeError) as error:
        raise BagError(f'{path}: not YAML: {error}') from error
    where = f'{path}: {ROOT}'
    if not isinstance(document, Mapping) or not isinstance(document.get(ROOT), Mapping):
        raise BagError(f'{path}: no {ROOT!r} mapping: not a rosbag2 metadata file')
    info = document[ROOT]
    topics = _get(info, 'topics_with_message_count', list, where)
    files = _get(info, 'relative_file_paths', list, where)
    if not all(isinstance(f, str) for f in files):
        raise BagError(f'{where}: relative_file_paths holds a name that is not a string')
    return BagMetadata(
        path=path, version=_get(info, 'version', int, where),
        storage_identifier=_get(info, 'storage_identifier', str, where),
        relative_file_paths=tuple(files),
        compression_format=str(info.get('compression_format') or '').lower(),
        compression_mode=str(info.get('compression_mode') or '').lower(),
        topics=tuple(_topic(t, f'{where}.topics_with_message_count[{i}]') for i, t in enumerate(topics)))
