"""CARMEN log files (``.clf``/``.log``, plain or gzip, chosen by content) read into records.

One message a line, ``#`` starts a comment (CARMEN's logger format; the layouts and their sources
are in :mod:`.carmen_messages`).  Read: ``ODOM``, ``FLASER``/``RLASER`` (old format),
``ROBOTLASER1``/``2``, ``RAWLASER1``..``4``, the old ``LASER3``/``LASER4`` and
``REMISSION*LASER*`` lines, ``TRUEPOS`` and ``PARAM``; ``SYNC`` lines are ignored (counted, no
warning); any other message type is skipped, counted and warned once per type.

The conventions follow CARMEN's own reader (``src/logtools/readlog.c``) and robot module;
docs/pluto-nav.md ("CARMEN logs") states each and why: stamps are a line's IPC ``timestamp``; the
old lines' beam angles are CARMEN's guess from the number of readings; a reading at or beyond the
laser's maximum range is ``inf`` (the beam saw nothing), one of 0 m or less NaN (no reading); the
mount comes from the line's laser and robot poses, else the ``robot_*laser_offset`` PARAM lines.
Records of one kind come out in time order: up to :data:`REORDER_WINDOW` seconds late they are put
in their place, older ones are dropped; :func:`.robot_log.load_log` sorts the kinds together.

Bad lines are counted per kind with ``file:line`` and warned once per kind; the reading goes on.
A damaged or cut gzip stream ends the reading with :meth:`LogProblems.error` naming the file and
the last good line; the records before it are kept.  A file with no scan and no odometry record
raises :class:`LogError`.
"""

from __future__ import annotations

import gzip
import heapq
import pathlib
import re
import zlib
from collections.abc import Iterator

from .carmen_messages import LineError, Mounts, parse_line
from .problems import LogError, LogProblems
from .records import LogRecord, OdometryRecord, ParamRecord, ScanRecord, TruePoseRecord

__all__ = ['REORDER_WINDOW', 'read_carmen']

#: Seconds a record may lie before the latest of its kind and still be put back in order.
REORDER_WINDOW = 5.0

_GZIP_MAGIC = b'\x1f\x8b'
_NOT_TEXT = re.compile(rb'[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]')


def _raw_lines(path: pathlib.Path, problems: LogProblems) -> Iterator[tuple[int, bytes]]:
    """``(line number, bytes)`` of every line; a damaged gzip stream ends them with an error."""
    try:
        with path.open('rb') as probe:
            compressed = probe.read(2) == _GZIP_MAGIC
        stream = gzip.open(path, 'rb') if compressed else path.open('rb')
    except OSError as error:
        raise LogError(f'{path}: cannot be read: {error.strerror or error}') from error
    lineno = 0
    with stream:
        lines = iter(stream)
        while True:
            try:
                raw = next(lines)
            except StopIteration:
                return
            except (OSError, EOFError, zlib.error) as error:
                what = 'gzip stream is damaged' if compressed else 'file cannot be read'
                problems.error(f'{path}: the {what} after line {lineno} ({error}); '
                               f'the records up to line {lineno} are kept')
                return
            lineno += 1
            yield lineno, raw


class _TimeOrder:
    """Puts each kind's records in time order within a window (see the module's description)."""

    def __init__(self, window: float, problems: LogProblems) -> None:
        self.window = window
        self.problems = problems
        self.latest: dict[str, float] = {}
        self.held: dict[str, list[tuple[float, int, LogRecord]]] = {}
        self.count = 0

    def push(self, kind: str, record: LogRecord, where: str) -> Iterator[LogRecord]:
        """Take ``record``; yield those of its kind that can no longer be overtaken."""
        stamp = record.stamp
        latest = self.latest.get(kind, stamp)
        if stamp < latest - self.window:
            self.problems.skip(f'{kind} record far back in time', where,
                               f'{latest - stamp:.3f} s before the latest {kind} record '
                               f'(more than the {self.window:g} s reordering window)')
            return
        if stamp < latest:
            self.problems.note('reordered', where, f'{kind} record {latest - stamp:.3f} s before '
                               f'the latest one: put back in time order')
        self.latest[kind] = max(latest, stamp)
        held = self.held.setdefault(kind, [])
        self.count += 1
        heapq.heappush(held, (stamp, self.count, record))
        horizon = self.latest[kind] - self.window
        while held and held[0][0] < horizon:
            yield heapq.heappop(held)[2]

    def flush(self) -> Iterator[LogRecord]:
        rest = [item for held in self.held.values() for item in held]
        self.held.clear()
        for _, _, record in sorted(rest, key=lambda item: (item[0], item[1])):
            yield record


def _kind(record: LogRecord) -> str:
    if isinstance(record, ScanRecord):
        return f'{record.channel} laser'
    if isinstance(record, OdometryRecord):
        return 'odometry'
    if isinstance(record, TruePoseRecord):
        return 'TRUEPOS'
    return type(record).__name__


def read_carmen(path: pathlib.Path, problems: LogProblems, *,
                reorder_window: float = REORDER_WINDOW) -> Iterator[LogRecord]:
    """Every record of the CARMEN log at ``path`` (see the module's description).

    :param path: the log, plain or gzip.
    :param problems: where bad lines, reordered records and a damaged gzip stream are reported.
    :param reorder_window: seconds a record of one kind may come late and still be put in its place;
        older ones are dropped.
    :raises LogError: the file cannot be opened, is empty, or holds no scan and no odometry.
    """
    mounts = Mounts()
    order = _TimeOrder(reorder_window, problems)
    usable = 0
    lines = 0
    for lineno, raw in _raw_lines(path, problems):
        lines += 1
        where = f'{path}:{lineno}'
        try:
            if _NOT_TEXT.search(raw):
                raise UnicodeError
            fields = raw.decode('utf-8').split()
        except UnicodeError:
            problems.skip('line that is not text', where)
            continue
        if not fields or fields[0].startswith('#'):
            continue
        if fields[0] == 'SYNC':
            problems.ignore('SYNC line')
            continue
        try:
            record = parse_line(fields, where, mounts)
        except LineError as error:
            problems.skip(error.kind, where, error.detail)
            continue
        if record is None:
            problems.skip(f'unsupported message type {fields[0][:40]}', where)
            continue
        if isinstance(record, ParamRecord):
            if not mounts.update(record.name, record.value):
                problems.note('PARAM laser mount that is not a number (ignored)', where,
                              f'{record.name} {record.value!r}')
            yield record
            continue
        usable += isinstance(record, (ScanRecord, OdometryRecord))
        yield from order.push(_kind(record), record, where)
    yield from order.flush()
    if lines == 0 and not problems.errors:
        raise LogError(f'{path}: an empty file')
    if usable == 0:
        said = f' ({problems.summary()})' if problems else ''
        raise LogError(f'{path}: no usable record: no laser scan or odometry line{said}')
