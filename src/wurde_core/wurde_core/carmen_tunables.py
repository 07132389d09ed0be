"""A module's tunables kept at the values of CARMEN's parameter daemon (the one documented way).

Every module's tunables (:mod:`wurde_core.parameters`: the drive's limits, the avoider's
distances, the poseModule's gates, the navigator's approach distance, a laser's settings) can
come from the robot's carmen.ini through ``param_daemon`` (Programming with CARMEN, 6).  A
module follows the daemon when its role configuration has the option ``param_daemon``
(global, or in the module's own ``<module>`` section), whose value is the daemon's node name
(``on`` for CARMEN's one daemon, ``/param_daemon``)::

    <option name="param_daemon" value="on"/>

Tunable ``name`` of module ``M`` is the CARMEN parameter ``M_name`` (:func:`carmen_name`).  Where
carmen.ini has it, its value wins over the module's options, defaults and ``--params-file``, and
later changes at the daemon are applied while the module runs (6.1); a value the tunable refuses
is reported and the tunable keeps its value; one carmen.ini does not name keeps its own, without a
warning (CARMEN's ``allow_unfound_variables``).  docs/carmen.md ("CARMEN's parameters") and
docs/wurde-core.md have the rest.

The link never blocks the module's loop: :meth:`DaemonTunables.poll`, called by the
CommsManager each turn, waits for the daemon's services without waiting (a daemon that starts
after the module is found when it comes), reads the module's values in two calls, subscribes,
and reads them once more when the daemon's parameter events are matched (a change made in
between would otherwise be lost).  A daemon that goes away or stops answering is looked for again;
one started again (a new writer of its parameter events) is read again.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable
from typing import Any

from .carmen_param import DAEMON, CarmenParams, DaemonError, ParamType, ParamTypeError, convert
from .parameters import Tunable, Tunables

__all__ = ['OPTION', 'DaemonTunables', 'carmen_name', 'daemon_of']

#: The role-configuration option that names the daemon.
OPTION = 'param_daemon'
#: Without the daemon this long after start, the module says so once (it keeps looking).
MISSING_NOTE_S = 10.0
#: How often a live link checks that the daemon is still the one it read (s): a daemon that went
#: away is looked for again, one started again is read again.
RECHECK_S = 1.0
_ILLEGAL = re.compile(r'[^A-Za-z0-9_]')
_KINDS = ((bool, ParamType.ONOFF), (int, ParamType.INT), (float, ParamType.DOUBLE),
          (str, ParamType.STRING))


def daemon_of(value: str) -> str | None:
    """The daemon node an option value names, or None for none.

    :param value: the ``param_daemon`` option's value: ``on``/``yes``/``true``/``1`` for CARMEN's
        (:data:`~wurde_core.carmen_param.DAEMON`), ``off``/``no``/``false``/``0``/``empty`` (the
        guide's value of an unset option) or empty for none, else a node name (``/`` added
        when missing).
    """
    text = value.strip()
    if text.lower() in ('', 'empty', 'off', 'no', 'false', '0'):
        return None
    if text.lower() in ('on', 'yes', 'true', '1'):
        return DAEMON
    return text if text.startswith('/') else '/' + text


def carmen_name(module: str, tunable: str) -> tuple[str, str]:
    """(CARMEN module, variable) of ``tunable`` of WURDE module ``module``: ``module_tunable``
    split where carmen.ini's names split, at the first ``_`` (``map_server``'s ``x`` is module
    ``map``, variable ``server_x``).

    :param module: the WURDE module's name; characters other than letters, digits and ``_``
        become ``_``.
    :param tunable: the tunable's name (``goto.reach``: its ``.`` becomes ``_``).
    """
    name = f'{_ILLEGAL.sub("_", module)}_{_ILLEGAL.sub("_", tunable)}'
    carmen_module, _, variable = name.partition('_')
    return carmen_module, variable


def _kind(tunable: Tunable) -> ParamType:
    return next(kind for type_, kind in _KINDS if isinstance(tunable.default, type_))


class DaemonTunables:
    """Keeps ``tunables`` of module ``module`` at the values the daemon serves."""

    def __init__(self, manager: Any, tunables: Tunables, daemon: str,
                 warn: Callable[[str], None],
                 client: Callable[[], CarmenParams] | None = None) -> None:
        """A link that is looking for the daemon; :meth:`poll` drives it.

        :param manager: the module's CommsManager (its name makes the CARMEN names).
        :param tunables: the module's tunables, set through their node like ``ros2 param set``.
        :param daemon: the daemon's node name (``/param_daemon``).
        :param warn: reports refusals and a missing or lost daemon.
        :param client: makes the CarmenParams; None: one for ``manager`` talking to ``daemon``.
        """
        self.daemon = daemon
        self._name = str(manager.name)
        self._module = carmen_name(self._name, 'x')[0]
        self._tunables = tunables
        self._warn = warn
        self._make = client or (lambda: CarmenParams(manager, daemon))
        self._params: CarmenParams | None = None
        self._state = 'looking'
        self._since = time.monotonic()
        self._noted = False
        self._writer: bytes | None = None
        self._checked = 0.0
        #: Values taken from the daemon, and refused, since start.
        self.applied = 0
        self.refused = 0

    @property
    def live(self) -> bool:
        """Whether the daemon's changes reach the module now."""
        return self._state == 'live'

    def _by_variable(self) -> dict[str, Tunable]:
        return {carmen_name(self._name, t.name)[1]: t for t in self._tunables.items()}

    def poll(self) -> None:
        """One step of the link (see the module docstring); never raises for the daemon."""
        try:
            self._poll()
        except DaemonError as error:
            self._warn(f'{self._name}: parameter daemon {self.daemon}: {error}; looking for '
                       'it again')
            self.close()
            self._state, self._since, self._noted = 'looking', time.monotonic(), True

    def _poll(self) -> None:
        if self._params is None:
            self._params = self._make()
        params = self._params
        if self._state == 'looking':
            if not params.services_ready():
                if not self._noted and time.monotonic() - self._since > MISSING_NOTE_S:
                    self._noted = True
                    self._warn(f'{self._name}: no parameter daemon {self.daemon} after '
                               f'{MISSING_NOTE_S:g} s; the tunables keep their values until it '
                               'answers')
                return
            for variable, tunable in self._by_variable().items():
                params.watch(self._module, variable, _kind(tunable), self._on_change)
            self._read_all()
            self._state = 'matching'
        if self._state == 'matching':
            if not params.events_matched():
                return
            self._writer = params.daemon_writer()
            self._read_all()            # what changed before the events reached us
            self._state, self._checked = 'live', time.monotonic()
        params.update()
        if time.monotonic() - self._checked >= RECHECK_S:
            self._checked = time.monotonic()
            writer = params.daemon_writer()
            if writer is None:          # gone: look for it (a new client) until it is back
                self._warn(f'{self._name}: parameter daemon {self.daemon} gone; looking for it')
                self.close()
                self._state, self._since, self._noted = 'looking', time.monotonic(), True
            elif writer != self._writer:  # started again while we looked away: its values
                self._state = 'matching'

    def _read_all(self) -> None:
        assert self._params is not None
        tunables = self._by_variable()
        for variable, value in self._params.served(self._module, sorted(tunables)).items():
            self._apply(tunables[variable], variable, value)

    def _on_change(self, _module: str, variable: str, value: Any) -> None:
        tunable = self._by_variable().get(variable)
        if tunable is not None:
            self._apply(tunable, variable, value)

    def _apply(self, tunable: Tunable, variable: str, value: Any) -> None:
        label = f'{self._module}_{variable}'
        try:
            value = convert(value, _kind(tunable), label)
        except ParamTypeError as error:
            self._refuse(f'{error}', tunable)
            return
        if value == tunable.value:
            return
        reason = self._tunables.set(tunable.name, value)
        if reason is None:
            self.applied += 1
        else:
            self._refuse(f'{label} = {value!r} refused: {reason}', tunable)

    def _refuse(self, what: str, tunable: Tunable) -> None:
        self.refused += 1
        self._warn(f'{what}; {tunable.name} stays {tunable.value!r}')

    def close(self) -> None:
        """Release the daemon client (idempotent)."""
        if self._params is not None:
            self._params.close()
            self._params = None
