"""Which reader a recording needs, chosen by its content, not its name."""

from __future__ import annotations

import pathlib
import zlib
from collections.abc import Iterator

from .problems import LogError, LogProblems
from .records import LogRecord

__all__ = ['open_records', 'sniff']

_MCAP_MAGIC = b'\x89MCAP'
_SQLITE_MAGIC = b'SQLite format 3\x00'
_GZIP_MAGIC = b'\x1f\x8b'


def sniff(path: pathlib.Path) -> str:
    """Which reader ``path`` needs: ``carmen`` or ``rosbag2``, by its content.

    :param path: a file, or a bag directory (with metadata.yaml, .mcap or .db3 files).
    :returns: ``carmen`` (a CARMEN log, plain or gzip) or ``rosbag2`` (a bag directory, its
        metadata.yaml, an .mcap or .db3 file).
    :raises LogError: missing, unreadable or of neither kind.
    """
    if path.is_dir():
        if (path / 'metadata.yaml').is_file() or any(path.glob('*.mcap')) or any(path.glob('*.db3')):
            return 'rosbag2'
        raise LogError(f'{path}: a directory with no metadata.yaml, .mcap or .db3 file: not a rosbag2 bag')
    try:
        with path.open('rb') as stream:
            head = stream.read(16)
    except OSError as error:
        raise LogError(f'{path}: cannot be read: {error.strerror or error}') from error
    if head.startswith(_MCAP_MAGIC) or head.startswith(_SQLITE_MAGIC) or path.name == 'metadata.yaml':
        return 'rosbag2'
    if not head:
        raise LogError(f'{path}: an empty file')
    compressed = head.startswith(_GZIP_MAGIC)
    text = _text_head(path, compressed)
    if not text.strip():
        raise LogError(f'{path}: an empty file' if not compressed else
                       f'{path}: a gzip file with no text in it (empty, or cut in its first block)')
    lines = text.splitlines()
    words = {line.split()[0] for line in lines[:-1] if line.split()}
    if lines and len(lines[-1].split()) > 1:   # a long first line cut by the sample: its name is whole
        words.add(lines[-1].split()[0])
    if words & _CARMEN_WORDS or text.lstrip().startswith('#'):
        return 'carmen'
    raise LogError(f'{path}: neither a CARMEN log (lines such as ODOM, FLASER, ROBOTLASER1) '
                   f'nor a rosbag2 bag (metadata.yaml, MCAP or SQLite)')


_CARMEN_WORDS = {'ODOM', 'FLASER', 'RLASER', 'ROBOTLASER1', 'ROBOTLASER2', 'RAWLASER1', 'RAWLASER2',
                 'RAWLASER3', 'RAWLASER4', 'TRUEPOS', 'PARAM', 'SYNC', 'LASER3', 'LASER4',
                 'REMISSIONFLASER', 'REMISSIONRLASER', 'REMISSIONLASER3', 'REMISSIONLASER4'}
_SAMPLE = 65536


def _text_head(path: pathlib.Path, compressed: bool) -> str:
    """The first bytes of the file's text, unpacked if gzip; a gzip stream that is cut or damaged
    further on still gives its beginning (the reader reports the damage where it is)."""
    try:
        with path.open('rb') as stream:
            data = stream.read(_SAMPLE)
        if compressed:
            unpacker = zlib.decompressobj(wbits=31)
            data = unpacker.decompress(data, _SAMPLE)
    except OSError as error:
        raise LogError(f'{path}: cannot be read: {error.strerror or error}') from error
    except zlib.error as error:
        raise LogError(f'{path}: a gzip file that cannot be unpacked: {error}') from error
    return data.decode('ascii', errors='replace')


def open_records(path: pathlib.Path, problems: LogProblems) -> Iterator[LogRecord]:
    """Every record of the recording at ``path``.

    The readers give each kind of record in time order (a CARMEN log within a reordering window;
    see :mod:`.carmen`).

    :param path: a CARMEN log or a rosbag2 bag, as :func:`sniff` takes it.
    :param problems: where the reader reports what it skipped, mended or could not read.
    :raises LogError: ``path`` is of neither kind (from :func:`sniff`).
    """
    kind = sniff(path)
    if kind == 'carmen':
        from .carmen import read_carmen
        return read_carmen(path, problems)
    from .rosbag import read_rosbag
    return read_rosbag(path, problems)
