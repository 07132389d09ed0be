"""A rosbag2 bag of any layout, opened as one stream of raw messages, and the types to decode them.

rosbags (pure Python: no ROS needed) reads the storage: a bag directory with ``metadata.yaml``
(split files in order, zstd file or message compression), that ``metadata.yaml`` itself, or one
``.mcap`` / ``.db3`` file.  It needs help with what real recordings also are, which is done here:

- a single storage file is chosen by its content, not its name;
- a directory without ``metadata.yaml`` (rosbag2 writes it last: a recorder that was killed
  leaves none) is read as one bag: its storage files' messages merged by time;
- an MCAP file rosbags cannot open (no footer or summary: the writer never finished) is read from
  its start with the ``mcap`` library's stream reader, up to where it ends;
- the types come from ROS 2 Jazzy's standard messages, plus the bag's own definitions of the
  others (rosbags' AnyReader takes only one of the two, so a bag that defines some types misses
  the rest); a type in neither cannot be read and is said so.
"""

from __future__ import annotations

import contextlib
import heapq
import pathlib
import re
from collections.abc import Collection, Iterator
from typing import Protocol

from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from rosbags.interfaces import (Connection, ConnectionExtRosbag2, MessageDefinition,
                                MessageDefinitionFormat)
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_types_from_idl, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from .problems import LogError, LogProblems

__all__ = ['Bag', 'bag_typestore', 'open_bag']

_MCAP_MAGIC = b'\x89MCAP0\r\n'
_SQLITE_MAGIC = b'SQLite format 3\x00'
_STORAGE_SUFFIXES = ('.mcap', '.db3')
_IDL_SEPARATOR = '=' * 80 + '\n'
_SCHEMA_FORMATS = {'ros2msg': MessageDefinitionFormat.MSG, 'ros2idl': MessageDefinitionFormat.IDL,
                   'omgidl': MessageDefinitionFormat.IDL}
RawMessage = tuple[Connection, int, bytes]


class Storage(Protocol):
    """What a bag is read from: rosbags' Reader, one of its storage plugins, or
    :class:`SequentialMcap`."""

    @property
    def connections(self) -> list[Connection]: ...

    def messages(self, connections: Collection[Connection]) -> Iterator[RawMessage]: ...

    def close(self) -> None: ...


class Bag:
    """An opened bag: its connections (one per topic and type) and their messages, by bag time."""

    def __init__(self, name: str, readers: list[Storage], problems: LogProblems) -> None:
        self.name = name
        self.problems = problems
        self._readers = readers
        self.connections: list[Connection] = [c for r in readers for c in r.connections]
        self._owner = {id(c): r for r in readers for c in r.connections}
        self._damaged: set[int] = set()

    def messages(self, connections: Collection[Connection]) -> Iterator[RawMessage]:
        """The messages of ``connections``, in bag time order.

        A file that breaks off or is damaged ends the stream: said once (``problems.error``), what came
        before is kept.

        :param connections: which of :attr:`connections` to read.
        :returns: ``(connection, bag time ns, CDR bytes)`` tuples.
        """
        streams = []
        for reader in self._readers:
            mine = [c for c in connections if self._owner[id(c)] is reader]
            if mine:
                streams.append(self._guarded(reader, mine))
        if len(streams) == 1:
            return streams[0]
        return heapq.merge(*streams, key=lambda m: m[1])

    def _guarded(self, reader: Storage, connections: list[Connection]) -> Iterator[RawMessage]:
        source = reader.messages(connections)
        last = None
        while True:
            try:
                item = next(source)
            except StopIteration:
                return
            except Exception as error:   # noqa: BLE001 -- damaged file data: any library error ends the reading
                if id(reader) not in self._damaged:
                    self._damaged.add(id(reader))
                    after = f'after bag time {last * 1e-9:.3f} s' if last is not None else 'at its start'
                    self.problems.error(f'{getattr(reader, "path", self.name)}: damaged {after}, the reading '
                                        f'stops there ({type(error).__name__}: {error})')
                return
            last = item[1]
            yield item


def _kind(path: pathlib.Path) -> str | None:
    try:
        with path.open('rb') as stream:
            head = stream.read(16)
    except OSError as error:
        raise LogError(f'{path}: cannot be read: {error.strerror or error}') from error
    if head.startswith(_MCAP_MAGIC):
        return '.mcap'
    if head.startswith(_SQLITE_MAGIC):
        return '.db3'
    return None


def _split_order(path: pathlib.Path) -> list[object]:
    """``bag_2.db3`` before ``bag_10.db3``."""
    return [int(p) if p.isdigit() else p for p in re.split(r'(\d+)', path.name)]


def _open_file(path: pathlib.Path, problems: LogProblems) -> Storage:
    kind = _kind(path)
    if kind is None:
        raise LogError(f'{path}: neither an MCAP nor an SQLite (.db3) rosbag2 storage file')
    storage = Reader.STORAGE_PLUGINS[kind](path)          # by content, whatever the file's name
    try:
        storage.open()
    except Exception as error:   # noqa: BLE001 -- rosbags raises several kinds for a damaged file
        if kind != '.mcap':
            raise LogError(f'{path}: not readable as a rosbag2 bag: {error}') from error
        sequential = SequentialMcap(path, problems)
        sequential.open(reason=str(error))
        return sequential
    return storage


def _close(readers: list[Storage]) -> None:
    for reader in readers:
        with contextlib.suppress(Exception):
            reader.close()


def _open_storages(path: pathlib.Path, problems: LogProblems, readers: list[Storage]) -> None:
    if path.is_dir():
        files = sorted((p for p in path.iterdir() if p.suffix in _STORAGE_SUFFIXES and p.is_file()),
                       key=_split_order)
        if (path / 'metadata.yaml').is_file():
            reader = Reader(path)
            try:
                reader.open()
                readers.append(reader)
            except Exception as error:   # noqa: BLE001 -- rosbags raises several kinds for a bad bag
                if 'serialization format' in str(error).lower() or not files:
                    raise LogError(f'{path}: not readable as a rosbag2 bag: {error}') from error
                problems.error(f'{path}/metadata.yaml: {error}; the storage files are read one by one')
        if not readers:
            if not files:
                raise LogError(f'{path}: no metadata.yaml, .mcap or .db3 file: not a rosbag2 bag')
            for file in files:
                readers.append(_open_file(file, problems))
    elif path.is_file():
        readers.append(_open_file(path, problems))
    else:
        raise LogError(f'{path}: no such file or directory')


@contextlib.contextmanager
def open_bag(path: pathlib.Path, problems: LogProblems) -> Iterator[Bag]:
    """The bag at ``path``, open until the ``with`` block exits.

    :param path: a bag directory, its metadata.yaml, or one storage file (.mcap, .db3).
    :param problems: where damage found while reading is reported.
    :raises LogError: missing, not a bag, a serialization other than CDR, or unreadable.
    """
    if path.name == 'metadata.yaml' and path.is_file():
        path = path.parent
    readers: list[Storage] = []
    try:
        try:
            _open_storages(path, problems, readers)
        except OSError as error:
            raise LogError(f'{path}: cannot be read: {error.strerror or error}') from error
        bag = Bag(str(path), readers, problems)
        other = sorted({f'{c.ext.serialization_format!r} ({c.topic})' for c in bag.connections
                        if isinstance(c.ext, ConnectionExtRosbag2) and c.ext.serialization_format != 'cdr'})
        if other:
            raise LogError(f'{path}: serialization format {", ".join(other)} is not supported (only CDR)')
        yield bag
    finally:
        _close(readers)


class SequentialMcap:
    """An MCAP file read from its start, record by record (the ``mcap`` library's stream reader):
    for a file without footer or summary, whose messages up to where it breaks off are good."""

    def __init__(self, path: pathlib.Path, problems: LogProblems) -> None:
        self.path = path
        self.problems = problems
        self.connections: list[Connection] = []
        self._by_channel: dict[int, Connection] = {}

    def open(self, reason: str) -> None:
        """Find the channels and count their messages (one pass over the file).

        :param reason: why the file is read without its index, for the notice in ``problems``.
        """
        schemas: dict[int, Schema] = {}
        counts: dict[int, int] = {}
        error = None
        try:
            for record in self._records():
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel) and record.id not in self._by_channel:
                    schema = schemas.get(record.schema_id)
                    definition = MessageDefinition(
                        _SCHEMA_FORMATS.get(schema.encoding, MessageDefinitionFormat.NONE) if schema
                        else MessageDefinitionFormat.NONE, schema.data.decode(errors='replace') if schema else '')
                    self._by_channel[record.id] = Connection(
                        record.id, record.topic, schema.name if schema else '', definition, '', 0,
                        ConnectionExtRosbag2(record.message_encoding, []), self)
                elif isinstance(record, Message):
                    counts[record.channel_id] = counts.get(record.channel_id, 0) + 1
        except Exception as broken:   # noqa: BLE001 -- a file cut off anywhere: any parse error
            error = broken
        self.connections = [c._replace(msgcount=counts.get(c.id, 0)) for c in self._by_channel.values()]
        self._by_channel = {c.id: c for c in self.connections}
        if error is None:
            self.problems.note('MCAP file read without its index', str(self.path), reason)
        else:
            detail = str(error) or 'the file ends inside a record'
            self.problems.error(f'{self.path}: the MCAP file breaks off (cut short or damaged: {detail}); '
                                f'the {sum(counts.values())} messages before the break are read')

    def _records(self) -> Iterator[object]:
        with self.path.open('rb') as stream:
            yield from StreamReader(stream, skip_magic=False).records

    def messages(self, connections: Collection[Connection]) -> Iterator[RawMessage]:
        wanted = {c.id for c in connections}
        try:
            for record in self._records():
                if isinstance(record, Message) and record.channel_id in wanted:
                    yield self._by_channel[record.channel_id], record.log_time, record.data
        except Exception:   # noqa: BLE001 -- the break already said at open
            return

    def close(self) -> None:
        """Nothing stays open between reads."""


def _definitions(definition: MessageDefinition, msgtype: str) -> dict:
    if definition.format == MessageDefinitionFormat.MSG:
        return get_types_from_msg(definition.data, msgtype)
    types: dict = {}
    if definition.data.startswith(f'{_IDL_SEPARATOR}IDL: '):
        for section in definition.data.split(_IDL_SEPARATOR)[1:]:
            types.update(get_types_from_idl(section.split('\n', 1)[1]))
    else:
        types.update(get_types_from_idl(definition.data))
    return types


def bag_typestore(connections: Collection[Connection]) -> tuple[Typestore, dict[str, str]]:
    """The types to decode ``connections``.

    :param connections: the bag's connections.
    :returns: a typestore of ROS 2 Jazzy's standard types and the bag's own definitions of the others,
        and for each type that cannot be read, why (type name -> reason).
    """
    store = get_typestore(Stores.ROS2_JAZZY)
    unreadable: dict[str, str] = {}
    for connection in connections:
        msgtype = connection.msgtype
        if msgtype in store.fielddefs or msgtype in unreadable:
            continue
        if connection.msgdef.format == MessageDefinitionFormat.NONE or not connection.msgdef.data.strip():
            unreadable[msgtype] = 'not a ROS 2 Jazzy standard type and the bag holds no definition of it'
            continue
        try:
            types = _definitions(connection.msgdef, msgtype)
            store.register({name: fields for name, fields in types.items() if name not in store.fielddefs})
            if msgtype not in store.fielddefs:
                unreadable[msgtype] = 'the bag\'s definition does not define it'
        except Exception as error:   # noqa: BLE001 -- a definition from the file: any parse error
            unreadable[msgtype] = f'its definition in the bag cannot be parsed ({error})'
    return store, unreadable
