"""What a motionModule keeps across its restarts by the MCP: whether its thread runs, the
rectangle, and the moveto it was driving, so that a restarted motionModule drives on (issue 38).

The state goes to the file the MCP gives the module (:class:`wurde_core.resume.ResumeState`); a
first start or a module started by hand ignores it.  An explore or investigate is not resumed: its
progress (lanes covered, the object circled) is not kept, and starting it over from where the robot
now stands would be another task; the thread comes back with the rectangle, and a client sees the
motion idle (element[3] 0 or -1).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from .motion_behaviours import Moveto
from .motion_command import MOVETO_SET, Rectangle
from .motion_control import MotionController

__all__ = ['restore', 'state_of']


def state_of(control: MotionController) -> dict[str, Any]:
    """The state to keep: ``running``, ``rectangle`` (its fields, or None) and ``moveto`` (the goal
    of the moveto running or paused, or None).

    :param control: the motionModule's controller.
    """
    moveto = next((b.goal for b in (control.behaviour, control.paused) if isinstance(b, Moveto)), None)
    return {'running': control.running,
            'rectangle': None if control.rectangle is None else dataclasses.asdict(control.rectangle),
            'moveto': None if moveto is None else list(moveto),
            'paused': control.behaviour is None and moveto is not None}


def _finite(values: Any, count: int) -> list[float] | None:
    if not isinstance(values, list) or len(values) != count:
        return None
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        return None
    return [float(v) for v in values]


def restore(control: MotionController, state: dict[str, Any]) -> str:
    """Put ``state`` (from :func:`state_of`, read back) into ``control``; what was resumed, for the
    log.  Fields that are missing or malformed are left at their defaults.

    :param control: the new process's controller.
    :param state: the saved state.
    """
    said = []
    rectangle = state.get('rectangle')
    if isinstance(rectangle, dict):
        values = _finite([rectangle.get(k) for k in ('b', 'h', 'x', 'y', 'theta')], 5)
        if values is not None:
            control.rectangle = Rectangle(*values)
            said.append('the rectangle')
    if isinstance(state.get('running'), bool):
        control.running = state['running']
        said.append('the thread running' if control.running else 'the thread stopped')
    goal = _finite(state.get('moveto'), 2)
    if goal is not None:
        moveto = control.moveto((goal[0], goal[1]))
        if state.get('paused') is True:
            control.paused = moveto
            said.append(f'the paused moveto ({goal[0]:.2f}, {goal[1]:.2f})')
        else:
            control.behaviour, control.paused, control.motion_code = moveto, None, None
            control.element2 = MOVETO_SET
            said.append(f'the moveto ({goal[0]:.2f}, {goal[1]:.2f})')
    return ', '.join(said) if said else 'nothing running'
