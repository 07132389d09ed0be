"""Where ``record`` writes: one MCAP file (:class:`McapSink`), or a rosbag2 bag directory of MCAP
files with ``metadata.yaml`` (:class:`BagDirectorySink`), both as rosbag2's MCAP storage writes.

Each file: profile ``ros2``; a ``ros2msg`` schema per type (its full definition); a channel per
topic, message encoding ``cdr``, with rosbag2's channel metadata ``offered_qos_profiles`` (YAML)
and ``topic_type_hash``; the CDR bytes as they travelled; and, before the summary, the metadata
record ``rosbag2`` with the bag's ``serialized_metadata`` (what ``ros2 bag info FILE.mcap`` reads).
A bag directory ``DIR`` holds ``DIR_0.mcap``, ``DIR_1.mcap``, ... (a new file when the messages in
the current one reach a size or span, as ``ros2 bag record -b`` / ``-d`` split) and, once closed,
``metadata.yaml`` (:mod:`.bag_metadata`).
"""

from __future__ import annotations

import dataclasses
import pathlib
import time
from collections.abc import Mapping
from typing import IO, Any

import yaml
from mcap.writer import Writer

from .bag_metadata import NO_TIME, FileEntry, TopicEntry, bagfile_information, dump, write_metadata
from .errors import BagError

__all__ = ['ROSBAG2_CHANNEL_KEYS', 'BagDirectorySink', 'McapSink', 'single_file_metadata']

#: The channel metadata rosbag2 reads; anything else a tap hands over stays out of the file.
ROSBAG2_CHANNEL_KEYS = ('offered_qos_profiles', 'topic_type_hash')
LIBRARY = 'wurde_mcp record'


@dataclasses.dataclass
class _Topic:
    """A channel as opened, and what the bag's metadata says of it."""

    name: str
    type_name: str
    definition: str
    metadata: dict[str, str]
    count: int = 0

    def entry(self) -> TopicEntry:
        text = self.metadata.get('offered_qos_profiles', '')
        return TopicEntry(self.name, self.type_name, 'cdr', (yaml.safe_load(text) or []) if text else [],
                          self.metadata.get('topic_type_hash', ''), self.count)


class McapSink:
    """One MCAP file a :class:`~.tap.TopicTap` writes into (through ``writer``, started by the
    caller with profile ``ros2``): a schema per type, a channel per topic."""

    def __init__(self, writer: Writer, name: str = '') -> None:
        """``name``: the file's name, for its ``files`` entry in the bag's metadata."""
        self.writer = writer
        self.name = name
        self.schemas: dict[str, int] = {}
        self.count = 0
        self.first = NO_TIME
        self.last = NO_TIME
        #: Per channel id: the topic it carries.
        self.topics: dict[int, _Topic] = {}

    def open_channel(self, topic: str, type_name: str, definition: str, metadata: Mapping[str, str]) -> int:
        """A channel for ``topic``; of ``metadata`` only rosbag2's keys are written."""
        return self.add(_Topic(topic, type_name, definition,
                               {k: metadata[k] for k in ROSBAG2_CHANNEL_KEYS if k in metadata}))

    def add(self, topic: _Topic) -> int:
        if topic.type_name not in self.schemas:
            self.schemas[topic.type_name] = self.writer.register_schema(topic.type_name, 'ros2msg',
                                                                        topic.definition.encode())
        channel = self.writer.register_channel(topic.name, 'cdr', self.schemas[topic.type_name], topic.metadata)
        self.topics[channel] = topic
        return channel

    def write(self, channel: int, data: bytes, log_time: int | None = None) -> None:
        """One message, stamped now unless ``log_time`` (ns) is given."""
        now = time.time_ns() if log_time is None else log_time
        self.writer.add_message(channel, log_time=now, data=data, publish_time=now, sequence=self.count)
        self.count += 1
        self.topics[channel].count += 1
        self.first = now if self.first == NO_TIME else min(self.first, now)
        self.last = now if self.last == NO_TIME else max(self.last, now)

    def file_entry(self) -> FileEntry:
        """This file's ``files`` entry."""
        return FileEntry(self.name, self.first, 0 if self.first == NO_TIME else self.last - self.first, self.count)

    def finish(self, bag: Mapping[str, Any]) -> None:
        """Write the ``rosbag2`` metadata record (``bag``: the bag's metadata document) and end
        the file."""
        self.writer.add_metadata('rosbag2', {'serialized_metadata': dump(bag['rosbag2_bagfile_information'])})
        self.writer.finish()


def single_file_metadata(sink: McapSink) -> dict[str, Any]:
    """The metadata document of a bag that is the one file of ``sink``."""
    return bagfile_information(storage_identifier='mcap', files=[sink.file_entry()],
                               topics=[t.entry() for t in sink.topics.values()])


class BagDirectorySink:
    """A rosbag2 bag directory a :class:`~.tap.TopicTap` writes into.  Life cycle: construct (no
    I/O), :meth:`open` (makes the directory and its first file), ``open_channel`` / ``write``,
    :meth:`close` (ends the last file, writes ``metadata.yaml``; idempotent)."""

    def __init__(self, directory: pathlib.Path, *, max_bytes: int = 0, max_seconds: float = 0.0) -> None:
        """A new file once the messages in the current one reach ``max_bytes`` (0: no limit) or
        span ``max_seconds`` (0: no limit)."""
        self.directory = directory
        self.max_bytes = max_bytes
        self.max_ns = int(max_seconds * 1e9)
        self.topics: list[_Topic] = []
        self.files: list[FileEntry] = []
        self.count = 0
        self._sink: McapSink | None = None
        self._stream: IO[bytes] | None = None
        self._channels: dict[int, int] = {}      # topic index -> channel id in the current file
        self._bytes = 0

    @property
    def paths(self) -> list[pathlib.Path]:
        """The storage files written so far, in order."""
        names = [f.path for f in self.files] + ([self._sink.name] if self._sink else [])
        return [self.directory / name for name in names]

    def open(self) -> None:
        """Make the directory and start its first file.

        :raises BagError: the directory exists already (rosbag2 does not write into one either)
            or cannot be made.
        """
        try:
            self.directory.mkdir(parents=True)
        except FileExistsError as error:
            raise BagError(f'{self.directory} exists already; a bag directory is written new') from error
        except OSError as error:
            raise BagError(f'{self.directory}: cannot be made: {error.strerror or error}') from error
        self._start()

    def _start(self) -> None:
        name = f'{self.directory.name}_{len(self.files)}.mcap'
        self._stream = (self.directory / name).open('wb')     # closed in _end
        writer = Writer(self._stream)
        writer.start(profile='ros2', library=LIBRARY)
        self._sink = McapSink(writer, name)
        self._channels = {index: self._sink.add(_Topic(t.name, t.type_name, t.definition, t.metadata))
                          for index, t in enumerate(self.topics)}
        self._bytes = 0

    def _end(self) -> None:
        assert self._sink is not None and self._stream is not None
        sink, self._sink = self._sink, None
        self.files.append(sink.file_entry())
        try:
            sink.finish(self.metadata())
        finally:
            self._stream.close()
            self._stream = None

    def metadata(self) -> dict[str, Any]:
        """The bag's metadata document as it stands (files ended so far)."""
        return bagfile_information(storage_identifier='mcap', files=self.files,
                                   topics=[t.entry() for t in self.topics])

    def open_channel(self, topic: str, type_name: str, definition: str, metadata: Mapping[str, str]) -> int:
        """A topic of the bag (its index), in every file from now on."""
        assert self._sink is not None, 'open() first'
        self.topics.append(_Topic(topic, type_name, definition,
                                  {k: metadata[k] for k in ROSBAG2_CHANNEL_KEYS if k in metadata}))
        index = len(self.topics) - 1
        self._channels[index] = self._sink.add(dataclasses.replace(self.topics[index]))
        return index

    def write(self, index: int, data: bytes) -> None:
        """One message of topic ``index``, stamped now; splits first when the file is full."""
        assert self._sink is not None, 'open() first'
        now = time.time_ns()
        if self._sink.count and ((self.max_bytes and self._bytes >= self.max_bytes)
                                 or (self.max_ns and now - self._sink.first >= self.max_ns)):
            self._end()
            self._start()
        self._sink.write(self._channels[index], data, now)
        self.topics[index].count += 1
        self._bytes += len(data)
        self.count += 1

    def close(self) -> pathlib.Path | None:
        """End the last file and write ``metadata.yaml``; its path (None when already closed)."""
        if self._sink is None:
            return None
        self._end()
        return write_metadata(self.directory, self.metadata())
