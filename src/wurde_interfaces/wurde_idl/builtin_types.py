"""The ``.msg`` files of the built-in types (seed: WURDE Programming Guide 3.1 and 3.2.4).

They are generated from the tables in :mod:`wurde_idl.types`, so the generator and the messages
can never disagree.  Coordinates are metres, angles radians, as the guide requires.
"""

from __future__ import annotations

from .types import BUILTIN_ENUMS, BUILTIN_MESSAGES

_DOCS = {
    'Point': 'A 2-D point (m) with a weight (guide 3.2.4: Point(x, y, w), value() is the weight).',
    'Point3D': 'A 3-D point (m) with a weight.',
    'Pose': 'A 2-D pose: position (m), heading theta (rad, about z), and a weight.',
    'Pose3D': ('A 3-D pose: position (m), orientation theta about z, then phi about y, then psi '
               'about x (rad; the Pluto convention), and a weight.'),
    'CVector': 'A Cartesian 2-D vector (m or m/s, by use).',
    'PVector': 'A polar 2-D vector: magnitude (m or m/s, by use) and angle (rad).',
    'RunState': 'Run state of a module, commanded by the MCP (guide 5.2.1).',
    'ProcessLocale': 'Whether a module runs on the MCP\'s machine (guide 6.1).',
    'ProcessType': 'How the MCP tracks a module: managed, unmanaged or critical (guide 6.1).',
    'StatusMode': ('A module\'s status as the MCP sees it.  The guide names the type only; '
                   'ZOMBIE is its word for a module whose heartbeat TTL expired.'),
    'ConnectionStrategy': 'How an object finds its stream (guide 6.3: STRAT_NORMAL/ASSIGNED/AUTO).',
}

_SUPPORT = {
    'Header': (
        '# Common header of every WURDE Data and Info message.\n'
        '# source: the supplier\'s tag (auto-tag, guide 3.2.1); empty when auto-tag is off and unset.\n'
        'string source\n'
        '# timestamp (auto-timestamp, guide 3.2.2); nanosecond resolution, so microseconds are exact.\n'
        'builtin_interfaces/Time stamp\n'
        '# sequence: counts the events one publisher sent on this channel, from 1; a receiver sees\n'
        '# lost events as gaps (queue mode counts them).  0 when the sender does not count.\n'
        'uint64 sequence\n'
        '# session: the sending process, a random number it drew when it started; 0 when the sender\n'
        '# does not say.  A receiver tells a restarted sender from the one before by it, however\n'
        '# far the new one\'s sequence has counted by the time the receiver looks.\n'
        'uint64 session\n'
    ),
    'Lock': (
        '# A lock on a Writable info member (guide 3.2.4): who may change it.\n'
        '# field: ROS field name of the member, or empty for the whole device.\n'
        'string field\n'
        'uint8 NONE=0\n'
        'uint8 SUPPLIERS=1\n'
        'uint8 CONSUMERS=2\n'
        'uint8 PROCESS=3\n'
        'uint8 mode\n'
        '# owner: the process name allowed to write when mode is PROCESS.\n'
        'string owner\n'
    ),
}


def builtin_messages() -> dict[str, str]:
    """Return ``{message name: .msg text}`` for the built-in types and the support messages."""
    result = dict(_SUPPORT)
    for name, fields in BUILTIN_MESSAGES.items():
        result[name] = f'# {_DOCS[name]}\n' + ''.join(f'float64 {f}\n' for f in fields)
    for name, values in BUILTIN_ENUMS.items():
        constants = ''.join(f'uint8 {value}={number}\n' for number, value in enumerate(values))
        result[name] = f'# {_DOCS[name]}\n{constants}uint8 value\n'
    return result
