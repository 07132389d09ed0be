"""The pose commands ``odoPose``, ``mapPose`` and ``utmPose`` and their push forms ``odoPosePush``,
``mapPosePush`` and ``utmPosePush`` (AU Robot Servers, "Online help": ``- odoPose odoPosePush``,
"Coordinate systems"; the seed's ``<push t=1.5 cmd="odopose pose"/>`` in "Server push").

As AURS's pose history module answers them: ``odoPose pose`` gives the newest pose in an
``<odoPose name="poses">`` block (the command's own tag), one ``<pose name="newest" x= y= h= tod=
vel= q=/>`` line (x, y, h with three decimals, tod with microseconds) and the closing tag; with no
option the reply is ``info="done"``, an unknown option ``warning="Unknown option: ..."``, and a pose
that has no source yet ``warning="No resources, missing utmPose ..."``.  Poses come from this
server's variables: ``odoPose.pose`` and ``mapPose.pose``; the UTM pose is computed from the GPS
fix (``gps.fix`` latitude and longitude, :mod:`.utm`), quality ``q`` the GGA fix quality.  No
history is kept, so only ``pose`` (the newest) is answered.

``odoPosePush cmd="odoPose pose" [i=N]`` runs the command on every N-th update of the pose's
structure, an update push (:class:`~.push.EventPush`) of the client like ``varpush``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

from .command import Command, closing, help_block, opening, reply
from .push import EventPush
from .push_commands import PushCommands
from .session import Session
from .utm import to_utm
from .variables import VariablePool

__all__ = ['POSES', 'PoseHistCommand', 'PosePushCommand', 'PoseSource', 'pose_help',
           'pose_push_help']


@dataclasses.dataclass(frozen=True)
class Pose:
    """One pose as the reply gives it."""

    x: float
    y: float
    h: float
    tod: float
    vel: float = 0.0
    q: float = 0.0


@dataclasses.dataclass(frozen=True)
class PoseSource:
    """Where one pose command reads its pose."""

    #: The command (``odoPose``); its push is ``<alias>Push``.
    alias: str
    #: The structure whose updates run its push.
    struct: str
    #: What the pose is, for the help.
    what: str
    #: The newest pose from the pool, or None with why there is none.
    read: Callable[[VariablePool], Pose | str]


def _values(pool: VariablePool, name: str) -> list[float] | None:
    var = pool.find(name)
    if var is None:
        return None
    value = var.current()
    return [float(v) for v in value] if isinstance(value, list) and value and \
        not isinstance(value[0], list) else None


def _pose_of(name: str) -> Callable[[VariablePool], Pose | str]:
    def read(pool: VariablePool) -> Pose | str:
        values = _values(pool, name)
        if values is None or len(values) < 3 or not all(map(math.isfinite, values[:3])):
            return f'no pose in {name} yet'
        vel = _values(pool, 'base.vel') if name.startswith('odo') else None
        return Pose(values[0], values[1], values[2], values[3] if len(values) > 3 else 0.0,
                    vel[0] if vel and math.isfinite(vel[0]) else 0.0)
    return read


def _utm(pool: VariablePool) -> Pose | str:
    fix = _values(pool, 'gps.fix')
    if fix is None or len(fix) < 5 or not all(map(math.isfinite, fix[:2])):
        return 'no GPS fix yet (gps.fix)'
    if fix[4] <= 0:
        return 'the GPS has no valid fix (GGA quality 0)'
    try:
        point = to_utm(fix[0], fix[1])
    except ValueError as exc:
        return str(exc)
    stamp = _values(pool, 'utmPose.pose')
    tod = stamp[3] if stamp and len(stamp) > 3 and math.isfinite(stamp[3]) else 0.0
    return Pose(point.easting, point.northing, math.nan, tod, 0.0, fix[4])


#: The three poses of "Coordinate systems".
POSES = (PoseSource('odoPose', 'odoPose', 'odometry pose', _pose_of('odoPose.pose')),
         PoseSource('utmPose', 'gps', 'UTM pose from the GPS fix', _utm),
         PoseSource('mapPose', 'mapPose', 'pose in the map', _pose_of('mapPose.pose')))


def pose_help(source: PoseSource) -> str:
    """``odoPose help``."""
    return (f'---------- Options to {source.alias} command\n'
            'help               This help list\n'
            f'pose               Get newest pose and time ({source.what})\n'
            '-------\n'
            f'See also {source.alias}Push (push on pose updates)')


def pose_push_help(source: PoseSource) -> str:
    """``odoPosePush help``."""
    return (f'----------------Available {source.alias}Push options:\n'
            'flush              Remove the push commands of this client\n'
            'interval=k or i=k  Push with this interval (in update count, def = 1)\n'
            'cmd="cmd"          \'cmd\' is the command to put on command queue on push event\n'
            'list               List all defined commands (as help text)\n'
            '---')


def _tod(seconds: float) -> str:
    if not math.isfinite(seconds) or seconds < 0:
        seconds = 0.0
    whole = math.floor(seconds)
    micro = min(999_999, round((seconds - whole) * 1e6))
    return f'{whole}.{micro:06d}'


class PoseHistCommand:
    """The ``odoPose`` (``mapPose``, ``utmPose``) handler over one pool."""

    def __init__(self, pool: VariablePool, source: PoseSource) -> None:
        self._pool = pool
        self._source = source

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        unknown = [key for key, _ in command.args if key.lower() != 'pose']
        if unknown:
            return [reply(tag, [('warning', f'Unknown option: {" ".join(unknown)}')])]
        if not command.has('pose'):
            return [reply(tag, [('info', 'done')])]
        pose = self._source.read(self._pool)
        if isinstance(pose, str):
            return [reply(tag, [('warning', f'No resources, missing {self._source.alias} '
                                            f'({pose})')])]
        line = reply('pose', [('name', 'newest'), ('x', f'{pose.x:.3f}'), ('y', f'{pose.y:.3f}'),
                              ('h', f'{pose.h:.3f}'), ('tod', _tod(pose.tod)),
                              ('vel', f'{pose.vel:.3f}'), ('q', f'{pose.q:g}')])
        return [opening(tag, [('name', 'poses')]), line, closing(tag)]


class PosePushCommand:
    """The ``odoPosePush`` (``mapPosePush``, ``utmPosePush``) handler."""

    def __init__(self, pool: VariablePool, pushes: PushCommands, source: PoseSource) -> None:
        self._pool = pool
        self._pushes = pushes
        self._source = source

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        mine = [push for push in client.pushes if isinstance(push, EventPush) and
                push.struct.lower() == self._source.struct.lower()]
        if command.has('list'):
            body = '\n'.join(f'{push.number}: i={push.every} count={push.count} cmd="{push.cmd}"'
                             for push in mine) or f'no {tag} commands'
            return help_block('Push command list', body, tag)
        if command.has('flush'):
            client.pushes[:] = [push for push in client.pushes if push not in mine]
            return [reply(tag, [('info', 'push command succeded - now 0 cmds and 0 calls')])]
        if not self._pool.is_struct(self._source.struct):
            return [reply(tag, [('warning', f'No interface resource (no {self._source.struct} '
                                            'in this server)')])]
        every = command.get('interval') or command.get('i')
        try:
            push = self._pushes.event_push(client, tag.lower(), command.get('cmd'),
                                           self._source.struct, every)
        except ValueError as exc:
            return [reply(tag, [('warning', f'push command failed: {exc}')])]
        client.pushes.append(push)
        return [reply(tag, [('info', f'push command succeded - now {len(mine) + 1} cmds and '
                                     '0 calls'), ('number', str(push.number))])]
