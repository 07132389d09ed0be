"""The localModule's resume file: where the robot was, so a restarted localModule goes on from there.

While it runs under an MCP the localModule keeps the state file the MCP gave it
(``WURDE_MCP_STATE``, :func:`wurde_core.resume.state_path`: ``<module name>.resume`` in the MCP's
module log directory) up to date; a process the MCP restarts
(``wurde_core.heartbeat.restart_count() > 0``) starts from it (:mod:`pluto_nav.local_module`).

The file is one JSON object, format ``pluto_nav.resume`` version 1 (docs/pluto-nav.md, "The
resume file", shows it): the base's odometry reading the poses correspond to, with the number and
the sender's session of the last odometry message taken (so that a restarted localModule knows
whether the base restarted too, :class:`wurde_core.sender_watch.SenderWatch`), stream (0)'s
dead-reckoned pose and stream (3)'s pose with its setter and holder, and the DMU's heading,
pitch and roll at that reading with its sender's session (``dmu``, null without a DMU); metres, radians, seconds,
covariances 3x3 over (x, y, theta) row by row.  It is written to a temporary file beside it
(``<file>.<pid>.tmp``) and renamed over it (``os.replace``), so a reader (or a process killed
while writing) never sees half a file.  :func:`read_resume` refuses anything else with a reason.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os

import numpy as np
from wurde_core.resume import replace_file

__all__ = ['FORMAT', 'VERSION', 'ResumeState', 'read_resume', 'to_json', 'write_resume']

FORMAT = 'pluto_nav.resume'
VERSION = 1


@dataclasses.dataclass(frozen=True)
class ResumeState:
    """What a restarted localModule needs to go on where the last one was."""

    odometry_stamp: float
    odometry: tuple[float, float, float]            # the base's odometry reading (x, y, theta)
    dead_reckoning: tuple[float, float, float]      # stream (0) at that reading
    dead_reckoning_covariance: np.ndarray           # 3x3
    pose: tuple[float, float, float]                # stream (3) at that reading
    pose_covariance: np.ndarray | None              # 3x3; None: that of dead reckoning
    setter: int = 0
    holder: str = ''
    #: The number of the base's odometry message (its header.sequence, from 1 per base process):
    #: a first sample numbered lower comes from a base restarted since (its odometry from zero).
    odometry_sequence: int = 0
    #: The base process's header.session (0: not known).
    odometry_session: int = 0
    #: The DMU's integrated heading (unwrapped), pitch and roll at the odometry reading (None:
    #: no DMU), and its process's header.session and last sequence: a restarted localModule whose
    #: DMU did not restart takes the heading turned meanwhile from the DMU, not the odometry.
    dmu: tuple[float, float, float] | None = None
    dmu_session: int = 0
    dmu_sequence: int = 0


class _Refused(Exception):
    pass


def _xyt(values: tuple[float, float, float] | np.ndarray) -> dict[str, float]:
    x, y, theta = (float(v) for v in values)
    return {'x': x, 'y': y, 'theta': theta}


def _matrix(matrix: np.ndarray) -> list[float]:
    return [float(v) for v in np.asarray(matrix, dtype=float).reshape(-1)]


def to_json(state: ResumeState) -> str:
    """The file's text for ``state``.

    :param state: what the localModule saves.
    """
    pose = {**_xyt(state.pose),
            'covariance': None if state.pose_covariance is None else _matrix(state.pose_covariance),
            'setter': int(state.setter), 'holder': state.holder}
    document = {'format': FORMAT, 'version': VERSION,
                'odometry': {'stamp': float(state.odometry_stamp), **_xyt(state.odometry),
                             'sequence': int(state.odometry_sequence),
                             'session': int(state.odometry_session)},
                'dead_reckoning': {**_xyt(state.dead_reckoning),
                                   'covariance': _matrix(state.dead_reckoning_covariance)},
                'pose': pose,
                'dmu': None if state.dmu is None else {
                    'theta': float(state.dmu[0]), 'phi': float(state.dmu[1]), 'psi': float(state.dmu[2]),
                    'sequence': int(state.dmu_sequence), 'session': int(state.dmu_session)}}
    return json.dumps(document) + '\n'


def write_resume(path: str | os.PathLike[str], state: ResumeState) -> None:
    """Write ``state`` to ``path`` atomically (:func:`wurde_core.resume.replace_file`).

    :param path: the resume file (the MCP's ``WURDE_MCP_STATE``).
    :param state: what to save.
    :raises OSError: when it cannot be written (the caller decides what that means).
    """
    replace_file(path, to_json(state))


def _object(document: dict, key: str) -> dict:
    value = document.get(key)
    if not isinstance(value, dict):
        raise _Refused(f'no "{key}" object')
    return value


def _number(section: dict, key: str, where: str) -> float:
    value = section.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _Refused(f'{where}.{key}: not a number ({value!r})')
    if not math.isfinite(value):
        raise _Refused(f'{where}.{key}: not finite')
    return float(value)


def _pose(section: dict, where: str) -> tuple[float, float, float]:
    return tuple(_number(section, key, where) for key in ('x', 'y', 'theta'))  # type: ignore[return-value]


def _covariance(section: dict, where: str) -> np.ndarray:
    values = section.get('covariance')
    if not isinstance(values, list) or len(values) != 9:
        raise _Refused(f'{where}.covariance: not a list of 9 numbers')
    numbers = {str(k): v for k, v in enumerate(values)}
    matrix = np.array([_number(numbers, str(k), f'{where}.covariance') for k in range(9)]).reshape(3, 3)
    scale = max(1.0, float(np.max(np.abs(matrix))))
    if not np.allclose(matrix, matrix.T, atol=1e-9 * scale) or np.min(np.linalg.eigvalsh(matrix)) < -1e-9 * scale:
        raise _Refused(f'{where}.covariance: not a covariance (symmetric, positive semidefinite)')
    return 0.5 * (matrix + matrix.T)


def _parse(text: str) -> ResumeState:
    try:
        document = json.loads(text)
    except json.JSONDecodeError as error:
        raise _Refused(f'not JSON (truncated?): {error}') from None
    if not isinstance(document, dict):
        raise _Refused('not a JSON object')
    if document.get('format') != FORMAT:
        raise _Refused(f'format is {document.get("format")!r}, not {FORMAT!r}')
    if document.get('version') != VERSION:
        raise _Refused(f'version {document.get("version")!r}, this program reads {VERSION}')
    odometry = _object(document, 'odometry')
    dead = _object(document, 'dead_reckoning')
    pose = _object(document, 'pose')
    setter = pose.get('setter', 0)
    if isinstance(setter, bool) or not isinstance(setter, int):
        raise _Refused(f'pose.setter: not an integer ({setter!r})')
    holder = pose.get('holder', '')
    if not isinstance(holder, str):
        raise _Refused(f'pose.holder: not a string ({holder!r})')
    sequence = odometry.get('sequence', 0)
    if isinstance(sequence, bool) or not isinstance(sequence, int) or sequence < 0:
        raise _Refused(f'odometry.sequence: not a count ({sequence!r})')
    session = odometry.get('session', 0)
    if isinstance(session, bool) or not isinstance(session, int) or session < 0:
        raise _Refused(f'odometry.session: not a session number ({session!r})')
    dmu, dmu_session, dmu_sequence = _dmu(document)
    return ResumeState(
        odometry_stamp=_number(odometry, 'stamp', 'odometry'), odometry=_pose(odometry, 'odometry'),
        dead_reckoning=_pose(dead, 'dead_reckoning'),
        dead_reckoning_covariance=_covariance(dead, 'dead_reckoning'),
        pose=_pose(pose, 'pose'),
        pose_covariance=None if pose.get('covariance') is None else _covariance(pose, 'pose'),
        setter=setter, holder=holder, odometry_sequence=sequence, odometry_session=session,
        dmu=dmu, dmu_session=dmu_session, dmu_sequence=dmu_sequence)


def _count(section: dict, key: str, where: str) -> int:
    value = section.get(key, 0)
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise _Refused(f'{where}.{key}: not a count ({value!r})')
    return value


def _dmu(document: dict) -> tuple[tuple[float, float, float] | None, int, int]:
    """The optional ``dmu`` object (absent or null in a file of a localModule without a DMU)."""
    section = document.get('dmu')
    if section is None:
        return None, 0, 0
    if not isinstance(section, dict):
        raise _Refused('"dmu" is not an object')
    angles = tuple(_number(section, key, 'dmu') for key in ('theta', 'phi', 'psi'))
    return angles, _count(section, 'session', 'dmu'), _count(section, 'sequence', 'dmu')  # type: ignore[return-value]


def read_resume(path: str | os.PathLike[str]) -> tuple[ResumeState | None, str]:
    """The state saved in the file at ``path``; never raises for a bad file.

    :param path: the resume file.
    :returns: ``(state, '')``, or ``(None, reason)`` when there is none or it is not a whole, valid
        resume file.
    """
    try:
        with open(path, encoding='utf-8') as stream:
            text = stream.read()
    except FileNotFoundError:
        return None, 'no such file'
    except OSError as error:
        return None, f'cannot read it: {error.strerror or error}'
    except UnicodeDecodeError:
        return None, 'not a text file'
    try:
        return _parse(text), ''
    except _Refused as refusal:
        return None, str(refusal)
