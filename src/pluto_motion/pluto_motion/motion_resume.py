"""What a motionModule keeps across its restarts by the MCP: whether its thread runs, the
rectangle, and the motion it was doing — a moveto's goal, an explore's points still to visit, an
investigate — so that a restarted motionModule carries on (issue 38).

The state goes to the file the MCP gives the module (:class:`wurde_core.resume.ResumeState`); a
first start or a module started by hand ignores it.  A paused motion (stopped by a pass-through
command, Pluto 6.3) comes back paused, for a resume (45) to continue.  An investigate starts over
from where the robot stands: what it saw of the object is not kept.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from .motion_behaviours import Explore, Investigate, Moveto
from .motion_command import MOVETO_SET, NO_MOVETO, Rectangle
from .motion_control import MotionController

__all__ = ['restore', 'state_of']

Behaviour = Moveto | Explore | Investigate


def _describe(behaviour: object) -> dict[str, Any] | None:
    if isinstance(behaviour, Moveto):
        return {'kind': 'moveto', 'goal': list(behaviour.goal)}
    if isinstance(behaviour, Explore):
        return {'kind': 'explore', 'points': [list(p) for p in behaviour.points]}
    if isinstance(behaviour, Investigate):
        return {'kind': 'investigate'}
    return None


def state_of(control: MotionController) -> dict[str, Any]:
    """The state to keep: ``running``, ``rectangle`` (its fields, or None), ``motion`` (the motion
    running or paused: its kind and what it still has to do, or None) and ``paused``.

    :param control: the motionModule's controller.
    """
    motion = _describe(control.behaviour) or _describe(control.paused)
    return {'running': control.running,
            'rectangle': None if control.rectangle is None else dataclasses.asdict(control.rectangle),
            'motion': motion,
            'paused': control.behaviour is None and motion is not None}


def _finite(values: Any, count: int) -> list[float] | None:
    if not isinstance(values, list) or len(values) != count:
        return None
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        return None
    return [float(v) for v in values]


def _rebuild(control: MotionController, motion: Any) -> tuple[Behaviour, int, str] | None:
    """The behaviour ``motion`` describes, the element[2] it starts with and its name for the log."""
    if not isinstance(motion, dict):
        return None
    kind = motion.get('kind')
    if kind == 'moveto':
        goal = _finite(motion.get('goal'), 2)
        if goal is None:
            return None
        return control.moveto((goal[0], goal[1])), MOVETO_SET, f'the moveto ({goal[0]:.2f}, {goal[1]:.2f})'
    if kind == 'explore' and control.rectangle is not None and isinstance(motion.get('points'), list):
        points = [_finite(p, 2) for p in motion['points']]
        if not points or any(p is None for p in points):
            return None
        explore = Explore(control.rectangle, control.moveto, control.settings)
        explore.points = [(p[0], p[1]) for p in points if p is not None]
        return explore, NO_MOVETO, f'the explore ({len(points)} points left)'
    if kind == 'investigate':
        return (Investigate(control.settings, control.inside, control.warn, wrist=control.wrist), NO_MOVETO,
                'the investigate (from the start)')
    return None


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
    rebuilt = _rebuild(control, state.get('motion'))
    if rebuilt is not None:
        behaviour, element2, name = rebuilt
        if state.get('paused') is True:
            control.paused = behaviour
            said.append(f'{name}, paused')
        else:
            control.behaviour, control.paused, control.motion_code = behaviour, None, None
            control.element2 = element2
            said.append(name)
    return ', '.join(said) if said else 'nothing running'
