"""The ``pt`` line of a robot controller: its odometry pose, kept in ``odoPose.pose``, unanswered.

Mobotware's robot controller ``mrc``, connected to a laser or camera server, sends on every
control tick (100 Hz) its odometry pose with the time of day (AU Robot Servers, "Coordinate
systems": odometry is ``odoPose``)::

    <pt tod="1286376207.875200" x="1.5310" y="-21.9120 " th="-2.0260 " />

As the AU Robot Servers' core does, :class:`PoseCommand` catches it before the command queue and
answers nothing; the pose becomes ``odoPose.pose`` (x, y, th, time) through :meth:`VariablePool.update
<.variables.VariablePool.update>`, so ``var odoPose.pose`` reads it and a ``varpush`` on
``odoPose`` runs on it.  docs/wurde-mcp.md ("The pt line") says which attributes are taken.

Before changing it: no history is kept, so memory does not grow however long a controller sends;
and a ``pt`` that cannot be read is warned about once per session, not once per line, so that a
controller with a broken pose line does not get a hundred warnings a second.
"""

from __future__ import annotations

import math

from .command import Command, reply
from .session import Session
from .variables import VariablePool

__all__ = ['ODO_POSE', 'PT_HELP', 'PoseCommand', 'PoseError', 'parse_pose']

#: The variable a controller's pose goes to.
ODO_POSE = 'odoPose.pose'

#: The attributes of a pose, each with the names AURS takes for it.
_NEEDED = (('tod',), ('x',), ('y',), ('th', 'h'))


class PoseError(ValueError):
    """A ``pt`` line that is not a pose; ``str()`` is the reason."""


def parse_pose(command: Command) -> tuple[float, float, float, float]:
    """``(x, y, th, tod)`` of a ``pt`` command; values may have spaces inside their quotes.

    :param command: the parsed ``pt`` line; ``th`` may be given as ``h``.
    :returns: x, y (m), th (rad) and the time of day tod (s since 1970).
    :raises PoseError: an attribute is missing, or is not a finite number.
    """
    values: list[float] = []
    for names in _NEEDED:
        text = next((command.get(name) for name in names if command.get(name) is not None), None)
        if text is None:
            raise PoseError(f'a pose needs {"/".join(names)}= (tod= x= y= th=)')
        try:
            value = float(text.strip())
        except ValueError:
            raise PoseError(f'{names[0]}="{text}" is not a number') from None
        if not math.isfinite(value):
            raise PoseError(f'{names[0]}="{text}" is not a finite number')
        values.append(value)
    tod, x, y, th = values
    return x, y, th, tod


class PoseCommand:
    """The ``pt`` handler over one pool: the pose into :data:`ODO_POSE`, no reply."""

    #: The key of :attr:`Session.told` for the once-per-session warning.
    TOLD = 'pt'

    def __init__(self, pool: VariablePool, variable: str = ODO_POSE) -> None:
        """Take poses into ``variable`` of ``pool``.

        :param pool: the server's variables.
        :param variable: the pose variable set; while the pool has no such variable, poses are
            dropped.
        """
        self._pool = pool
        self._variable = variable

    def __call__(self, client: Session, command: Command) -> list[str]:
        try:
            x, y, th, tod = parse_pose(command)
        except PoseError as exc:
            if self.TOLD in client.told:
                return []
            client.told.add(self.TOLD)
            return [reply(command.tag, [('warning', f'{exc}: pose not taken (said once)')])]
        if tod <= 0.0 and abs(x) <= 0.01:             # AURS: a controller with no pose yet
            return []
        if self._pool.find(self._variable) is not None:
            self._pool.update(self._variable, [x, y, th, tod])
        return []


#: ``pt help``.
PT_HELP = ('-------------------- PT (from a robot controller, e.g. mrc):\n'
           'tod=T x=X y=Y th=H      The odometry pose at time T (s since 1970): kept as\n'
           f'                        {ODO_POSE}; no reply (a pose that cannot be read is\n'
           '                        warned about once per client)')
