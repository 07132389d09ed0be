"""The xmlServer's variable tree of the robot: one table from Mobotware variable names to WURDE
streams and the members of their messages.

Pluto (section 2): the xmlServer is "a translation program between mobility and a much simpler xml
interface using sockets".  Every variable is a row of :data:`ROWS`; :class:`RobotPool` makes one
consumer per stream of the table and copies the named members into the pool as messages arrive —
there is no handler per variable, so a new variable is a new row.  Stream names are templates over
the robot's device names (``{base}``, ``{laser}``, ``{gps}``: :data:`DEVICE_DEFAULTS`, as in
``config/pluto``).  docs/wurde-mcp.md ("The robot's variables") has the table of variables,
streams and members.

Before changing it: a ``*.command`` variable is written as ``cmdFlags p0 p1 [v0 v1 [f0]]`` (Pluto
4 and 6): only the members given go to the stream's request channel, so the link's Writable locks
apply and a locked member is refused with the lock's reason; it reads back the link's echo of the
command it runs.  ``odoPose.pose`` is also set by a client's ``pt`` line (:mod:`.pose_command`);
the newer of the two is read.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any, cast

from wurde_core import CommsManager, LockedError, RobotObject, RunState, StatusMode, WurdeError
from wurde_core.heartbeat import mcp_name
from wurde_core.interfaces import robot_object_class
from wurde_core.mcp_client import control_stream

from .variables import Value, VarError, Variable, VariablePool

__all__ = ['DEVICE_DEFAULTS', 'ROWS', 'RobotPool', 'Row']

#: The device names the stream templates are filled with unless the command line says otherwise.
DEVICE_DEFAULTS = {'base': 'PlutoBase', 'laser': 'PlutoLaser', 'gps': 'PlutoGPS'}


def _member(message: Any, path: str) -> Any:
    for name in path.split('.'):
        message = getattr(message, name)
    return message


def _numbers(message: Any, paths: Sequence[str]) -> list[float]:
    """The members ``paths`` of ``message`` as one list of doubles (sequences flattened)."""
    values: list[float] = []
    for path in paths:
        member = _member(message, path)
        if isinstance(member, (int, float, bool)):
            values.append(float(member))
        else:
            values.extend(float(v) for v in member)
    return values


@dataclasses.dataclass(frozen=True)
class Row:
    """One row of the table: a variable fed by members of one stream's data."""

    #: The Mobotware name (``odoPose.pose``).
    var: str
    #: The WURDE stream, a template over :data:`DEVICE_DEFAULTS`'s keys.
    stream: str
    #: Its interface.
    interface: str
    #: ``pose`` (members x, y, th: the message's stamp is added), ``d`` or ``s``.
    typ: str
    #: Dotted member paths in the stream's ROS message (``pose.x``; ``nan`` for a missing one).
    members: tuple[str, ...]
    #: What ``var desc`` prints.
    description: str
    #: A ``*.command`` variable: writes go to the stream's request channel (ActuatorState).
    command: bool = False


def _chain(link: str, stream: str, what: str) -> tuple[Row, ...]:
    return (
        Row(f'{link}.status', f'{stream}/status', 'FVectorState', 'd', ('element',),
            f'(r) {what} status codes element[] (Pluto 6)'),
        Row(f'{link}.data', f'{stream}/status', 'FVectorState', 'd', ('data',),
            f'(r) {what} status values data[] (Pluto 6)'),
        Row(f'{link}.command', f'{stream}/command', 'ActuatorState', 'd', ('cmd_flags', 'position'),
            f'(r/w) {what} command: cmdFlags p0 p1 [v0 v1 [f0]]; reads the command it runs', command=True),
    )


#: The table (see the module's docstring).
ROWS: tuple[Row, ...] = (
    Row('odoPose.pose', 'Localization/Dead-Reckoning', 'LocalizationPose', 'pose',
        ('pose.x', 'pose.y', 'pose.theta'), '(r) dead-reckoning pose x, y (m), th (rad), time (s)'),
    Row('mapPose.pose', 'Localization/Pose', 'LocalizationPose', 'pose',
        ('pose.x', 'pose.y', 'pose.theta'), '(r) pose in the map x, y (m), th (rad), time (s)'),
    Row('mapPose.setter', 'Localization/Pose', 'LocalizationPose', 'd', ('cmd_flags',),
        '(r) who set the pose: 0 nobody, 1 pose, 2 slam, 3 slam saving, <0 a robot pose'),
    Row('utmPose.pose', '{gps}', 'GPS', 'pose', ('x', 'y', 'nan'),
        '(r) GPS position x east, y north (m, local grid around the origin), no heading (nan)'),
    Row('gps.fix', '{gps}', 'GPS', 'd', ('latitude', 'longitude', 'altitude', 'satellites', 'quality', 'hdop'),
        '(r) latitude, longitude (deg), altitude (m), satellites, GGA quality, HDOP'),
    Row('base.pose', '{base}Motion', 'Egomotion', 'pose', ('location.x', 'location.y', 'location.theta'),
        '(r) raw odometry x, y (m), th (rad), time (s)'),
    Row('base.vel', '{base}Motion', 'Egomotion', 'd', ('tv', 'rv'), '(r) velocity: linear (m/s), angular (rad/s)'),
    Row('base.power', '{base}Power', 'Power', 'd', ('voltage', 'charge'), '(r) battery voltage (V), charge (0..1)'),
    Row('laser.ranges', '{laser}', 'RangeFinder', 'd', ('ranges',), '(r) the newest scan, ranges (m)'),
    *_chain('drive', 'drive', 'driveModule'),
    *_chain('avoid', 'avoidance', 'avoidModule'),
    *_chain('motion', 'motion', 'motionModule'),
)

#: The MCP's module table (SimpleControl data on this stream) gives ``mcp.<module>.*``.


class RobotPool:
    """A :class:`VariablePool` kept current from the streams of :data:`ROWS` by :meth:`refresh`."""

    def __init__(self, manager: CommsManager, devices: dict[str, str] | None = None,
                 rows: Sequence[Row] = ROWS) -> None:
        """Make the variables (empty, a pose NaN, until their stream's first message) and their
        consumers.

        :param manager: the xmlServer's manager; the consumers are registered with it.
        :param devices: device names by template key (``base``, ``laser``, ``gps``) where they
            differ from :data:`DEVICE_DEFAULTS`; None: the defaults.
        :param rows: the table (the tests pass a smaller one).
        """
        names = {**DEVICE_DEFAULTS, **(devices or {})}
        self.pool = VariablePool()
        self._streams: dict[str, RobotObject] = {}
        self._rows: dict[str, list[Row]] = {}
        for row in rows:
            stream = row.stream.format(**names)
            if stream not in self._streams:
                obj = robot_object_class(row.interface)(stream)
                manager.register_consumer(obj)
                self._streams[stream] = obj
            self._rows.setdefault(stream, []).append(row)
            write = self._command_writer(self._streams[stream], row.var) if row.command else None
            initial: Value = [math.nan] * (4 if row.typ == 'pose' else 0) if row.typ != 's' else ''
            self.pool.add(Variable(row.var, row.typ, row.description, initial, write=write))
        self.pool.describe('', 'the robot (Pluto) through the WURDE streams')
        self._mcp = robot_object_class('SimpleControl')(control_stream(mcp_name()))
        manager.register_consumer(self._mcp)

    def refresh(self) -> int:
        """Copy what arrived on every stream into the pool; the number of messages taken in."""
        taken = 0
        for stream, obj in self._streams.items():
            while obj.get_next_data():
                taken += 1
                message = obj.data.ros_message()
                stamp = obj.data.timestamp.get_seconds()
                for row in self._rows[stream]:
                    self.pool.update(row.var, self._value(row, message, stamp))
        while self._mcp.get_next_data():
            taken += 1
            self._modules(self._mcp.data)
        return taken

    @staticmethod
    def _value(row: Row, message: Any, stamp: float) -> Value:
        if row.typ == 's':
            return ' '.join(str(_member(message, path)) for path in row.members)
        values = [math.nan if path == 'nan' else v for path in row.members
                  for v in (_numbers(message, (path,)) if path != 'nan' else [math.nan])]
        return values + [stamp] if row.typ == 'pose' else values

    def _modules(self, table: Any) -> None:
        """``mcp.<module>.state`` and friends from one module table (made on first sight)."""
        rows = zip(table.module_names, table.module_state, table.module_status, table.module_pid,
                   table.module_restarts)
        for name, state, status, pid, restarts in rows:
            values: dict[str, tuple[str, Value, str]] = {
                'state': ('s', RunState(state).name, '(r) run state: RUN, IDLE, RESET, RESTART or QUIT'),
                'status': ('s', StatusMode(status).name, '(r) what the MCP sees of it (heartbeat status)'),
                'pid': ('d', [float(pid)], '(r) process id'),
                'restarts': ('d', [float(restarts)], '(r) restarts by the MCP so far'),
            }
            for member, (typ, value, description) in values.items():
                var = f'mcp.{name}.{member}'
                if self.pool.find(var) is None:
                    self.pool.add(Variable(var, typ, description, value))
                self.pool.update(var, value)

    @staticmethod
    def _command_writer(obj: RobotObject, var: str) -> Callable[[Value], None]:
        """The writer of a ``*.command`` variable: cmdFlags p0 p1 [v0 v1 [f0]] as a request."""
        def write(value: Value) -> None:
            numbers = [float(v) for v in cast(list[float], value)]  # a 'd' variable's value
            if not numbers or not numbers[0].is_integer():
                raise VarError(f'{var} is cmdFlags p0 p1 [v0 v1 [f0]], cmdFlags a whole number')
            if not all(math.isfinite(v) for v in numbers):
                raise VarError(f'{var}: every value must be finite')
            if not obj.peers('request'):
                raise VarError(f'{var}: nobody reads {obj.stream} yet (is its module running?)')
            while obj.get_next_info():                  # the supplier's newest Writable locks
                pass
            req = obj.requests
            try:                                        # only the members given are written
                req.cmd_flags.set_value(int(numbers[0]))
                for member, values in (('position', numbers[1:3]), ('velocity', numbers[3:5]),
                                       ('force', numbers[5:6])):
                    if values:
                        getattr(req, member).set_value(values)
            except (LockedError, WurdeError) as exc:
                raise VarError(f'{var}: {exc}') from None
            if not obj.publish_request():
                raise VarError(f'{var}: not sent (the server is not in Run)')
        return write

