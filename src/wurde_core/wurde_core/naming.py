"""Stream names to ROS topic names, by one documented and reversible rule.

A stream ``S`` lives at ``wurde/S/data``, ``wurde/S/info`` and ``wurde/S/request`` below the node's
namespace: ``/wurde/S/data`` for a module started plainly, ``/robot1/wurde/S/data`` for one started
with ``--ros-args -r __ns:=/robot1`` (so two robots share a domain without cross-talk).  ``S`` is
split at ``/`` (Pluto's ``Localization/Dead-Reckoning`` becomes two levels).  A segment that is
already a plain ROS name token — a letter, then letters and digits, single underscores between
them — is kept as it is.  Any other segment is written ``w__`` followed by the segment with every
character other than a letter or digit replaced by ``_`` and its UTF-8 bytes in two upper-case hex
digits each (``Dead-Reckoning`` -> ``w__Dead_2DReckoning``, ``Laser_Dead-Reckoning`` ->
``w__Laser_5FDead_2DReckoning``).  Kept segments never contain ``__``, encoded ones always start
with ``w__``, so :func:`stream_name` undoes :func:`stream_segment_path` exactly.
"""

from __future__ import annotations

import re

from .errors import WurdeError

#: The first level of every stream topic, below the namespace.
ROOT = 'wurde'
CHANNELS = ('data', 'info', 'request')
_PLAIN = re.compile(r'^[A-Za-z][A-Za-z0-9]*(_[A-Za-z0-9]+)*$')
_MARK = 'w__'
_ESCAPE = re.compile(r'_([0-9A-F]{2})')


def _encode(segment: str) -> str:
    if _PLAIN.match(segment):
        return segment
    out = [_MARK]
    for char in segment:
        if char.isascii() and char.isalnum():
            out.append(char)
        else:
            out.extend(f'_{byte:02X}' for byte in char.encode())
    return ''.join(out)


def _decode(segment: str) -> str:
    if not segment.startswith(_MARK):
        return segment
    raw = bytearray()
    body = segment[len(_MARK):]
    pos = 0
    while pos < len(body):
        if body[pos] == '_':
            raw.append(int(body[pos + 1:pos + 3], 16))
            pos += 3
        else:
            raw.extend(body[pos].encode())
            pos += 1
    return raw.decode()


def stream_segment_path(stream: str) -> str:
    """The topic path of ``stream`` below :data:`ROOT` (``Localization/w__Dead_2DReckoning``).

    :param stream: a stream name, its levels separated by ``/``.
    :raises WurdeError: for an empty stream name or an empty segment (``a//b``, ``/a``).
    """
    segments = stream.split('/')
    if not stream or any(not s for s in segments):
        raise WurdeError(f'stream name {stream!r} is empty or has an empty segment')
    return '/'.join(_encode(s) for s in segments)


def relative_topic(stream: str, channel: str) -> str:
    """The topic of one channel of ``stream``, relative: a node resolves it in its namespace.

    :param stream: a stream name.
    :param channel: ``data``, ``info`` or ``request``.
    :raises ValueError: for another channel.
    :raises WurdeError: for an empty stream name or segment.
    """
    if channel not in CHANNELS:
        raise ValueError(f'unknown channel {channel!r}')
    return f'{ROOT}/{stream_segment_path(stream)}/{channel}'


def _namespace_prefix(namespace: str) -> str:
    return namespace.rstrip('/') + '/'


def topic(stream: str, channel: str, namespace: str = '/') -> str:
    """The absolute ROS topic of one channel of ``stream`` in ``namespace``.

    :param stream: a stream name.
    :param channel: ``data``, ``info`` or ``request``.
    :param namespace: the node's namespace (``/robot1``); ``/`` for a module started plainly.
    """
    return _namespace_prefix(namespace) + relative_topic(stream, channel)


def typed_view(stream: str, interface: str) -> str:
    """The stream on which a module supplies ``stream`` as a second interface.

    A stream has one interface; a module that serves the same thing as two (a base's RobotDrive
    and SynchroDrive) supplies the second on ``<stream>/<interface>``, and the MCP assigns it to a
    mapping of that interface to ``stream`` (WURDE guide 1.1.5 and appendix 10.1 map one base's
    drive as either).

    :param stream: the stream of the first interface.
    :param interface: the second interface's name (``SynchroDrive``).
    """
    return f'{stream}/{interface}'


def stream_name(topic_name: str, namespace: str = '/') -> tuple[str, str]:
    """Undo :func:`topic`: ``<namespace>/wurde/<path>/<channel>`` -> ``(stream, channel)``.

    :param topic_name: an absolute topic name.
    :param namespace: the namespace it is in (``/`` for a module started plainly).
    :raises WurdeError: when ``topic_name`` is not a WURDE stream topic of ``namespace``.
    """
    prefix = _namespace_prefix(namespace) + ROOT + '/'
    if not topic_name.startswith(prefix):
        raise WurdeError(f'{topic_name!r} is not below {prefix}')
    path, _, channel = topic_name[len(prefix):].rpartition('/')
    if channel not in CHANNELS or not path:
        raise WurdeError(f'{topic_name!r} is not a WURDE stream topic')
    return '/'.join(_decode(s) for s in path.split('/')), channel
