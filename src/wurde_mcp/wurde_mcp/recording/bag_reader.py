"""A rosbag2 bag of any layout, opened as its topics and one time-ordered stream of raw messages.

What ``replay`` reads:

- a bag directory with ``metadata.yaml`` (as ``ros2 bag record`` and ``record -o DIR`` write it),
  or that ``metadata.yaml`` itself: its files in ``relative_file_paths`` order, in MCAP or sqlite3
  storage; zstd file compression (``NAME_0.mcap.zstd``, ``.db3.zstd``: each file is decompressed
  into a temporary directory while the bag is open) and zstd message compression.  The topics,
  their serialization format and their QoS come from the metadata, as ``ros2 bag play`` takes them;
- a directory without ``metadata.yaml`` (a recorder stopped before writing it): its ``.mcap`` and
  ``.db3`` files, in split order (``x_2`` before ``x_10``), a file that cannot be opened (the last
  one, left unfinished) skipped with a warning;
- one storage file, ``.mcap`` or ``.db3``, whatever its name (chosen by content).

The storage files are read by rosbags' readers (pure Python: ROS's own rosbag2 is not on PyPI).
rosbags' directory reader is not used: it drops the messages of a topic whose QoS in
``metadata.yaml`` differs from the one in the storage file (Foxy's "infinite" durations, for one),
and rosbag2's own test bags ``talker`` and ``cdr_test`` then read as empty.  Messages of several
files are merged by time.  In an MCAP file written by this suite before it wrote rosbag2's
``offered_qos_profiles``, each channel's ``durability`` and ``reliability`` metadata are kept
(:attr:`BagTopic.legacy`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import heapq
import pathlib
import re
import tempfile
from collections.abc import Collection, Iterator, Mapping
from typing import Any

import yaml
import zstandard
from mcap.reader import make_reader
from rosbags.rosbag2 import Reader

from .bag_metadata import METADATA_FILE, BagMetadata, read_metadata
from .errors import BagError
from .message_types import normalize_type
from .qos import Offer, offers_from_yaml

__all__ = ['Bag', 'BagTopic', 'open_bag']

_MCAP_MAGIC = b'\x89MCAP0\r\n'
_SQLITE_MAGIC = b'SQLite format 3\x00'
_KINDS = {'mcap': '.mcap', 'sqlite3': '.db3'}
_LEGACY_KEYS = ('durability', 'reliability')


@dataclasses.dataclass(frozen=True, eq=False)
class BagTopic:
    """One topic of a bag (with one type); each is its own (compared and hashed by identity)."""

    name: str
    #: ``pkg/msg/Name`` (``pkg/Name`` of old bags made so).
    type_name: str
    serialization_format: str
    #: What each recorded publisher offered (empty: not recorded).
    offers: tuple[Offer, ...]
    #: This suite's older ``durability`` / ``reliability`` channel metadata, if any.
    legacy: Mapping[str, str]
    message_count: int


@dataclasses.dataclass
class _Storage:
    """One opened storage file and which topic each of its connections carries."""

    path: pathlib.Path
    reader: Any
    topics: dict[int, BagTopic]


class Bag:
    """An opened bag: :attr:`topics` and :meth:`messages`; :attr:`warnings` says what was
    read in a way of its own (a QoS that could not be read, a directory without metadata)."""

    def __init__(self, path: pathlib.Path, topics: list[BagTopic], storages: list[_Storage],
                 message_compression: bool, warnings: list[str]) -> None:
        self.path = path
        self.topics = topics
        self.warnings = warnings
        self._storages = storages
        self._message_compression = message_compression

    def messages(self, topics: Collection[BagTopic]) -> Iterator[tuple[BagTopic, int, bytes]]:
        """``(topic, bag time ns, CDR bytes)`` of ``topics``, in time order.

        :raises BagError: a storage file is damaged where it is read (named).
        """
        wanted = set(topics)
        streams = []
        for storage in self._storages:
            connections = [c for c in storage.reader.connections if storage.topics.get(c.id) in wanted]
            if connections:
                streams.append(self._read(storage, connections))
        return heapq.merge(*streams, key=lambda item: item[1])

    def _read(self, storage: _Storage, connections: list[Any]) -> Iterator[tuple[BagTopic, int, bytes]]:
        decompressor = zstandard.ZstdDecompressor() if self._message_compression else None
        source = storage.reader.messages(connections)
        while True:
            try:
                connection, stamp, data = next(source)
                if decompressor is not None:
                    data = decompressor.decompressobj().decompress(data)
            except StopIteration:
                return
            except Exception as error:  # noqa: BLE001 -- damaged file data: any library error
                raise BagError(f'{storage.path}: damaged ({type(error).__name__}: {error})') from error
            yield storage.topics[connection.id], stamp, bytes(data)


def _kind(path: pathlib.Path) -> str:
    """``.mcap`` or ``.db3`` by the file's first bytes."""
    try:
        with path.open('rb') as stream:
            head = stream.read(16)
    except OSError as error:
        raise BagError(f'{path}: cannot be read: {error.strerror or error}') from error
    if head.startswith(_MCAP_MAGIC):
        return '.mcap'
    if head.startswith(_SQLITE_MAGIC):
        return '.db3'
    raise BagError(f'{path}: neither an MCAP nor an SQLite (.db3) rosbag2 storage file')


def _legacy(path: pathlib.Path) -> dict[str, dict[str, str]]:
    """Per topic, the older ``durability`` / ``reliability`` channel metadata of an MCAP file."""
    try:
        with path.open('rb') as stream:
            summary = make_reader(stream).get_summary()
    except Exception:  # noqa: BLE001 -- only a hint; rosbags has read the file already
        return {}
    if summary is None:
        return {}
    return {c.topic: {k: c.metadata[k] for k in _LEGACY_KEYS if k in c.metadata}
            for c in summary.channels.values()}


def _open_storage(path: pathlib.Path, shown: pathlib.Path, stack: contextlib.ExitStack) -> Any:
    """rosbags' reader of one storage file, open until ``stack`` closes."""
    kind = _kind(path)
    reader = Reader.STORAGE_PLUGINS[kind](path)
    try:
        reader.open()
    except Exception as error:  # noqa: BLE001 -- rosbags raises several kinds for a bad file
        raise BagError(f'{shown}: not readable as a rosbag2 storage file ({error})') from error
    stack.callback(reader.close)
    return reader


def _file_topics(path: pathlib.Path, reader: Any) -> dict[int, BagTopic]:
    """The topics of a storage file read on its own, from its own connections."""
    legacy = _legacy(path) if _kind(path) == '.mcap' else {}
    topics = {}
    for connection in reader.connections:
        offers = tuple(Offer(q.reliability.name.lower(), q.durability.name.lower())
                       for q in connection.ext.offered_qos_profiles)
        topics[connection.id] = BagTopic(connection.topic, normalize_type(connection.msgtype),
                                         connection.ext.serialization_format, offers,
                                         legacy.get(connection.topic, {}), connection.msgcount)
    return topics


def _metadata_topics(metadata: BagMetadata, warnings: list[str]) -> list[BagTopic]:
    topics = []
    for entry in metadata.topics:
        try:
            offers = offers_from_yaml(entry.offered_qos_profiles)
        except (ValueError, yaml.YAMLError) as error:
            warnings.append(f'{metadata.path}: {entry.name}: offered_qos_profiles cannot be read ({error}); '
                            'replayed reliable and volatile')
            offers = ()
        topics.append(BagTopic(entry.name, normalize_type(entry.type), entry.serialization_format, offers, {},
                               entry.message_count))
    return topics


def _decompressed(path: pathlib.Path, stack: contextlib.ExitStack) -> pathlib.Path:
    """A zstd-compressed storage file decompressed into a temporary directory."""
    directory = pathlib.Path(stack.enter_context(tempfile.TemporaryDirectory(prefix='replay-')))
    target = directory / (path.name[:-len('.zstd')] if path.name.endswith('.zstd') else path.name)
    try:
        with path.open('rb') as source, target.open('wb') as sink:
            zstandard.ZstdDecompressor().copy_stream(source, sink)
    except OSError as error:
        raise BagError(f'{path}: cannot be decompressed: {error.strerror or error}') from error
    except zstandard.ZstdError as error:
        raise BagError(f'{path}: not a zstd-compressed file ({error})') from error
    return target


def _open_directory(directory: pathlib.Path, stack: contextlib.ExitStack,
                    warnings: list[str]) -> tuple[list[BagTopic], list[_Storage], bool]:
    metadata = read_metadata(directory)
    if metadata.storage_identifier not in _KINDS:
        raise BagError(f'{metadata.path}: storage {metadata.storage_identifier!r} is not supported '
                       f'(only {", ".join(_KINDS)})')
    mode = '' if metadata.compression_mode in ('', 'none') else metadata.compression_mode
    if mode not in ('', 'file', 'message'):
        raise BagError(f'{metadata.path}: compression mode {metadata.compression_mode!r} is not supported')
    if mode and metadata.compression_format != 'zstd':
        raise BagError(f'{metadata.path}: compression format {metadata.compression_format!r} is not supported '
                       '(only zstd)')
    # Older rosbag2 wrote the paths with the bag's directory in front: the file's own name counts.
    paths = [directory / pathlib.PurePath(name).name for name in metadata.relative_file_paths]
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        raise BagError(f'{metadata.path}: the bag\'s file {", ".join(missing)} is missing')
    topics = _metadata_topics(metadata, warnings)
    by_key = {(t.name, t.type_name): t for t in topics}
    by_name = {t.name: t for t in topics}
    storages = []
    for path in paths:
        readable = _decompressed(path, stack) if mode == 'file' else path
        reader = _open_storage(readable, path, stack)
        mapping = {}
        for connection in reader.connections:
            topic = by_key.get((connection.topic, normalize_type(connection.msgtype))) \
                or by_name.get(connection.topic)
            if topic is None:             # in the file but not in metadata.yaml: take the file's word
                topic = _file_topics(readable, reader)[connection.id]
                topics.append(topic)
                by_key[(topic.name, topic.type_name)] = by_name[topic.name] = topic
            mapping[connection.id] = topic
        storages.append(_Storage(path, reader, mapping))
    return topics, storages, mode == 'message'


def _split_order(path: pathlib.Path) -> list[Any]:
    """``bag_2.mcap`` before ``bag_10.mcap``."""
    return [(0, int(p)) if p.isdigit() else (1, p) for p in re.split(r'(\d+)', path.name)]


def _open_files(paths: list[pathlib.Path], stack: contextlib.ExitStack,
                warnings: list[str] | None = None) -> tuple[list[BagTopic], list[_Storage]]:
    """Storage files read on their own: one topic per name and type across them.  With
    ``warnings``, a file that cannot be opened (the one a killed recorder left unfinished) is
    skipped and said there."""
    opened = []
    for path in paths:
        try:
            reader = _open_storage(path, path, stack)
        except BagError as error:
            if warnings is None:
                raise
            warnings.append(f'{error}; skipped')
            continue
        opened.append((path, reader, _file_topics(path, reader)))
    first: dict[tuple[str, str], BagTopic] = {}
    counts: dict[tuple[str, str], int] = {}
    for _, _, file_topics in opened:
        for topic in file_topics.values():
            key = (topic.name, topic.type_name)
            first.setdefault(key, topic)
            counts[key] = counts.get(key, 0) + topic.message_count
    merged = {key: dataclasses.replace(topic, message_count=counts[key]) for key, topic in first.items()}
    storages = [_Storage(path, reader, {cid: merged[(t.name, t.type_name)] for cid, t in file_topics.items()})
                for path, reader, file_topics in opened]
    return list(merged.values()), storages


@contextlib.contextmanager
def open_bag(path: pathlib.Path) -> Iterator[Bag]:
    """The bag at ``path`` (a bag directory, its ``metadata.yaml``, or one storage file), open
    until the block ends.

    :raises BagError: missing, not a bag, a storage or compression not supported, or unreadable.
    """
    if path.name == METADATA_FILE and path.is_file():
        path = path.parent
    warnings: list[str] = []
    with contextlib.ExitStack() as stack:
        compressed = False
        if path.is_dir() and (path / METADATA_FILE).is_file():
            topics, storages, compressed = _open_directory(path, stack, warnings)
        elif path.is_dir():
            files = sorted((p for p in path.iterdir() if p.suffix in ('.mcap', '.db3') and p.is_file()),
                           key=_split_order)
            if not files:
                raise BagError(f'{path}: no {METADATA_FILE}, .mcap or .db3 file: not a rosbag2 bag')
            warnings.append(f'{path}: no {METADATA_FILE}; its {len(files)} storage files are read one by one')
            topics, storages = _open_files(files, stack, warnings)
        elif path.is_file():
            topics, storages = _open_files([path], stack)
        else:
            raise BagError(f'{path}: no such file or directory')
        yield Bag(path, topics, storages, compressed, warnings)
