"""CARMEN's parameter interface for any module: parameters from the running ``param_daemon``.

The calls of "Programming with CARMEN", section 6, on ROS 2 parameters::

    params = CarmenParams(manager)                   # the daemon is /param_daemon
    speed = params.get_double('robot_max_t_vel')     # carmen_param_get_double
    params.set_module('robot')                       # carmen_param_set_module
    flipped = params.get_onoff('laser_flipped')      # None, and a warning, if not defined

The daemon serves ``module_variable`` of carmen.ini as its ROS 2 parameter ``module.variable``;
here names are spelt as CARMEN spells them.  Where the seed is silent (docs/carmen.md, "CARMEN's
parameters", has the user's side): a missing parameter is ``None``, a value that does not convert
raises :class:`ParamTypeError` (a wrong carmen.ini); targets are ``(obj, 'attr')`` or
``(mapping, key)``, as Python has no pointers; changes are applied in the program's own thread by
:meth:`CarmenParams.update` (and while any other call of this object waits for the daemon), as
CARMEN applied them in the program's IPC dispatch.  Handlers never run in another thread.

How it talks to the daemon: through rclpy's :class:`~rclpy.parameter_client.AsyncParameterClient`
on a node of its own in the module's context (one context, one DDS participant per process), spun
by its own executor only while a call waits (each with a deadline).  The module's CommsManager
polls its node without an executor and serves no service clients, so neither can block or starve
the other.  A program whose manager has opened no node (``param_tool``) gets a context here.
"""

from __future__ import annotations

import atexit
import re
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import rclpy
from rcl_interfaces.msg import ParameterEvent
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import qos_profile_parameter_events
from rclpy.signals import SignalHandlerOptions

from .carmen_values import (DaemonError, Handler, Param, ParamError, ParamExit, ParamType,
                            ParamTypeError, Target, as_served, assign, convert, param_table, text_of,
                            typed_value)
from .errors import InvalidValueError

__all__ = ['CALL_WAIT_S', 'DAEMON', 'REREAD', 'SERVICE_WAIT_S', 'CarmenParams', 'DaemonError',
           'Param', 'ParamError', 'ParamExit', 'ParamType', 'ParamTypeError', 'convert',
           'param_table', 'text_of', 'typed_value']

#: The daemon's node, as CARMEN has one parameter server.
DAEMON = '/param_daemon'
#: The daemon's parameter that makes it re-read its carmen.ini when set to true.
REREAD = 'reread'
#: Longest wait for the daemon's parameter services to be discovered (a loaded machine).
SERVICE_WAIT_S = 30.0
#: Longest wait for one answer of the daemon.
CALL_WAIT_S = 10.0
#: A request not answered within this is sent again (every request here is idempotent): a service
#: found ready by its client can still drop an answer on a loaded machine, when the daemon's reply
#: writer has not yet matched this client's reader (discovery runs both ways, not at once).
RESEND_S = 1.0
#: Longest wait for the daemon's parameter events to reach a new subscription.
MATCH_WAIT_S = 10.0
_EVENTS = '/parameter_events'

@dataclass(frozen=True)
class _Subscription:
    kind: ParamType
    target: Target | None
    handler: Handler | None


class CarmenParams:
    """The parameter interface of one program (libparam_interface), talking to ``daemon``.

    Nothing is opened until the first call; :meth:`close` (also at exit) releases it.
    """

    def __init__(self, manager: Any, daemon: str = DAEMON) -> None:
        """A client of ``daemon`` for the program of ``manager``; nothing is opened yet.

        :param manager: the program's CommsManager (its name names this client's node, which
            lives in the manager's context); anything with a ``name`` for a program without one.
        :param daemon: the daemon's node name; a leading ``/`` is added when missing.
        """
        self.daemon = daemon if daemon.startswith('/') else '/' + daemon
        self._node_name = re.sub(r'[^A-Za-z0-9_]', '_', str(manager.name)) + '_carmen_param'
        self._manager = manager
        self._own_context = False
        self._module: str | None = None
        self._allow_unfound = False
        self._subscriptions: dict[str, list[_Subscription]] = {}
        self._context: Context | None = None
        self._node: Any = None
        self._executor: SingleThreadedExecutor | None = None
        self._client: AsyncParameterClient | None = None
        self._events: Any = None
        self._received = 0
        self._ready = False
        self._closed = False

    # -- connection ----------------------------------------------------------------------------
    def open(self) -> None:
        """Connect to the daemon (done by the first call that needs it).

        :raises DaemonError: when its parameter services are not found within
            :data:`SERVICE_WAIT_S`.
        """
        if self._ready:
            return
        if self._closed:
            raise ParamError('this CarmenParams was closed')
        if self._node is None:
            self._create()
        assert self._client is not None
        deadline = time.monotonic() + SERVICE_WAIT_S
        while not self._client.services_are_ready():
            if time.monotonic() > deadline:
                raise DaemonError(f'no parameter daemon {self.daemon} within {SERVICE_WAIT_S} s')
            time.sleep(0.05)
        self._ready = True

    def services_ready(self) -> bool:
        """Whether the daemon's parameter services are there now (no waiting; creates this
        client's node on the first call).  A module that must not block polls this each turn."""
        if self._closed:
            return False
        if self._node is None:
            self._create()
        assert self._client is not None
        self._ready = self._ready or self._client.services_are_ready()
        return self._ready

    def _create(self) -> None:
        opener = getattr(self._manager, '_open', None)   # a CommsManager: its node, now
        if opener is not None:
            opener()
        context = getattr(self._manager, 'context', None)
        if context is None:
            context = Context()
            rclpy.init(args=['carmen_param'], context=context,
                       signal_handler_options=SignalHandlerOptions.NO)
            self._own_context = True
        try:
            self._node = rclpy.create_node(self._node_name, context=context,
                                           start_parameter_services=False, enable_rosout=False)
            self._executor = SingleThreadedExecutor(context=context)
            self._executor.add_node(self._node)
            self._client = AsyncParameterClient(self._node, self.daemon)
        finally:
            self._context = context
        atexit.register(self.close)

    def close(self) -> None:
        """Release the node and its context; idempotent."""
        if self._closed:
            return
        self._closed = True
        atexit.unregister(self.close)
        if self._executor is not None:
            self._executor.shutdown()
        if self._node is not None and self._context is not None and self._context.ok():
            self._node.destroy_node()   # (a module's context shut down first took it along)
        if self._context is not None and self._own_context:
            self._context.try_shutdown()

    def __enter__(self) -> 'CarmenParams':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _call(self, send: Callable[[], Any]) -> Any:
        """The answer to the request ``send()`` makes (a future), sent again every
        :data:`RESEND_S` until answered or :data:`CALL_WAIT_S` have passed."""
        assert self._executor is not None
        deadline = time.monotonic() + CALL_WAIT_S
        while True:
            future = send()
            self._executor.spin_until_future_complete(
                future, timeout_sec=max(0.0, min(RESEND_S, deadline - time.monotonic())))
            if future.done():
                return future.result()
            future.cancel()
            if time.monotonic() >= deadline:
                raise DaemonError(f'{self.daemon} did not answer within {CALL_WAIT_S} s')

    def served(self, module: str, variables: Sequence[str]) -> dict[str, Any]:
        """The daemon's values of those ``module_variable`` of ``variables`` it has, unconverted,
        by variable: two calls for any number (a module's whole table at start).

        :param module: the CARMEN module name (``robot``).
        :param variables: variable names within ``module`` (``max_t_vel``); those the daemon
            lacks are left out of the result.
        :raises DaemonError: when the daemon does not answer.
        """
        values = self._fetch([f'{module}.{variable}' for variable in variables])
        return {name.split('.', 1)[1]: value for name, value in values.items()}

    def _fetch(self, names: Sequence[str]) -> dict[str, Any]:
        """The served values of those of ``names`` the daemon has (ROS names)."""
        self.open()
        assert self._client is not None
        client = self._client
        declared = set(self._call(lambda: client.list_parameters(
            sorted({n.split('.', 1)[0] for n in names}))).result.names)
        present = [n for n in names if n in declared]
        if not present:
            return {}
        values = self._call(lambda: client.get_parameters(present)).values
        return {n: parameter_value_to_python(v) for n, v in zip(present, values)}

    # -- getting parameters (6) ------------------------------------------------------------------
    def set_module(self, module: str | None) -> None:
        """carmen_param_set_module: bare variable names are looked up in ``module`` (6).

        :param module: the module for later gets and sets; None or empty: names must be
            ``module_variable``.
        """
        self._module = module or None

    def allow_unfound_variables(self, allow: bool = True) -> None:
        """carmen_param_allow_unfound_variables: no warning for a missing parameter, and
        :meth:`install_params` does not exit on one (6, 6.2).

        :param allow: True to allow missing parameters, False for the default (warn, exit).
        """
        self._allow_unfound = bool(allow)

    def _candidates(self, name: str) -> list[str]:
        """ROS names for ``name``: after set_module, ``module.name`` first, then ``name`` itself
        as fully qualified if it can be."""
        names = [f'{self._module}.{name}'] if self._module else []
        module, _, variable = name.partition('_')
        if module and variable:
            names.append(f'{module}.{variable}')
        if not names:
            raise InvalidValueError(f'{name!r} is not module_variable, and no module was set')
        return names

    def _get(self, name: str, kind: ParamType, caller: str) -> Any:
        """Section 6: the value converted on demand, or None after the unfound warning."""
        candidates = self._candidates(name)
        values = self._fetch(candidates)
        for ros in candidates:
            if ros in values:
                return convert(values[ros], kind, ros.replace('.', '_', 1))
        self._unfound(name, caller)
        return None

    def _unfound(self, name: str, caller: str) -> None:
        if not self._allow_unfound:
            shown = f'{self._module}_{name}' if self._module and '_' not in name else name
            print(f'WARNING: {caller}: the parameter server {self.daemon} has no definition for '
                  f'{shown} (is carmen.ini out of date?)', file=sys.stderr, flush=True)

    def get_int(self, name: str) -> int | None:
        """carmen_param_get_int.

        :param name: ``module_variable``, or the variable after :meth:`set_module` (looked up in
            that module first).
        :returns: the value, or None (after a warning on stderr unless unfound variables are
            allowed) when the daemon has no such parameter.
        :raises ParamTypeError: for a value that is not an integer.
        :raises DaemonError: when the daemon is not found or does not answer.
        """
        return self._get(name, ParamType.INT, 'get_int')

    def get_double(self, name: str) -> float | None:
        """carmen_param_get_double (an int is a fine double).

        :param name: ``module_variable``, or the variable after :meth:`set_module`.
        :returns: the value, or None when the daemon has no such parameter (as :meth:`get_int`).
        :raises ParamTypeError: for a value that is not a number.
        """
        return self._get(name, ParamType.DOUBLE, 'get_double')

    def get_onoff(self, name: str) -> bool | None:
        """carmen_param_get_onoff: True for on, False for off.

        :param name: ``module_variable``, or the variable after :meth:`set_module`.
        :returns: the value, or None when the daemon has no such parameter (as :meth:`get_int`).
        :raises ParamTypeError: for a value that is not on/off.
        """
        return self._get(name, ParamType.ONOFF, 'get_onoff')

    def get_string(self, name: str) -> str | None:
        """carmen_param_get_string: any value, as its text (on/off for a bool).

        :param name: ``module_variable``, or the variable after :meth:`set_module`.
        :returns: the text, or None when the daemon has no such parameter (as :meth:`get_int`).
        """
        return self._get(name, ParamType.STRING, 'get_string')

    # -- subscribing to changes (6.1) ----------------------------------------------------------
    def _subscribe(self, module: str, variable: str, kind: ParamType | str, target: Target | None,
                   handler: Handler | None, *, wait: bool = True) -> None:
        """6.1: set ``target`` to each new value, then call ``handler(module, variable, value)``.
        Without ``wait``, returns before the daemon's events are matched: the caller polls
        :meth:`events_matched` and reads the values again once they are."""
        self.open()
        if self._events is None:
            self._events = self._node.create_subscription(ParameterEvent, _EVENTS, self._on_event,
                                                          qos_profile_parameter_events)
            if wait:
                self._wait_matched()
        self._subscriptions.setdefault(f'{module}.{variable}', []).append(
            _Subscription(ParamType(kind), target, handler))

    def watch(self, module: str, variable: str, kind: ParamType, handler: Handler) -> None:
        """A subscription (6.1) that does not wait for the daemon's events to be matched: for
        a loop that must not block (see :meth:`events_matched`).

        :param module: the CARMEN module name.
        :param variable: the variable within ``module``.
        :param kind: the type each new value is converted to (a value that does not convert is
            ignored with a warning).
        :param handler: called ``handler(module, variable, value)`` by :meth:`update`.
        :raises DaemonError: when the daemon is not found.
        """
        self._subscribe(module, variable, kind, None, handler, wait=False)

    def events_matched(self) -> bool:
        """Whether the daemon's parameter events reach this client's subscription now (no
        waiting; False before the first subscription)."""
        if self._events is None:
            return False
        writers = self._node.get_publishers_info_by_topic(_EVENTS)
        return (self._daemon_writer(writers) is not None
                and self._events.get_publisher_count() >= len(writers))

    def daemon_writer(self) -> bytes | None:
        """The identity (DDS GID) of the daemon's parameter-event writer now, or None when the
        daemon is not in the graph: a new identity is a daemon that was started again."""
        if self._node is None:
            return None
        return self._daemon_writer(self._node.get_publishers_info_by_topic(_EVENTS))

    def _daemon_writer(self, writers: Sequence[Any]) -> bytes | None:
        for writer in writers:
            if '/' + f'{writer.node_namespace}/{writer.node_name}'.strip('/') == self.daemon:
                return bytes(writer.endpoint_gid)
        return None

    def _wait_matched(self) -> None:
        """Until the daemon's parameter events reach the subscription (a change made before
        would be lost: the topic keeps no history), at most :data:`MATCH_WAIT_S`."""
        assert self._executor is not None
        deadline = time.monotonic() + MATCH_WAIT_S
        while time.monotonic() < deadline:
            if self.events_matched():
                return
            self._executor.spin_once(timeout_sec=0.05)
        print(f'WARNING: the parameter events of {self.daemon} did not arrive within '
              f'{MATCH_WAIT_S} s; changes may be missed', file=sys.stderr, flush=True)

    def subscribe_int(self, module: str, variable: str, target: Target | None = None,
                      handler: Handler | None = None) -> None:
        """carmen_param_subscribe_int (6.1): follow the daemon's changes of one parameter.
        Waits (at most :data:`MATCH_WAIT_S`) for the daemon's parameter events at the first
        subscription; the changes are applied by :meth:`update`.

        :param module: the CARMEN module name (``robot``).
        :param variable: the variable within ``module`` (``max_t_vel``).
        :param target: ``(obj, 'attr')`` or ``(mapping, key)`` set to each new value; None: none.
        :param handler: called ``handler(module, variable, value)`` after the target is set;
            None: none.
        :raises DaemonError: when the daemon is not found.
        """
        self._subscribe(module, variable, ParamType.INT, target, handler)

    def subscribe_double(self, module: str, variable: str, target: Target | None = None,
                         handler: Handler | None = None) -> None:
        """carmen_param_subscribe_double (6.1), as :meth:`subscribe_int`.

        :param module: the CARMEN module name.
        :param variable: the variable within ``module``.
        :param target: ``(obj, 'attr')`` or ``(mapping, key)`` set to each new value; None: none.
        :param handler: called ``handler(module, variable, value)`` after the target is set.
        """
        self._subscribe(module, variable, ParamType.DOUBLE, target, handler)

    def subscribe_onoff(self, module: str, variable: str, target: Target | None = None,
                        handler: Handler | None = None) -> None:
        """carmen_param_subscribe_onoff (6.1), as :meth:`subscribe_int`.

        :param module: the CARMEN module name.
        :param variable: the variable within ``module``.
        :param target: ``(obj, 'attr')`` or ``(mapping, key)`` set to each new value; None: none.
        :param handler: called ``handler(module, variable, value)`` after the target is set.
        """
        self._subscribe(module, variable, ParamType.ONOFF, target, handler)

    def subscribe_string(self, module: str, variable: str, target: Target | None = None,
                         handler: Handler | None = None) -> None:
        """carmen_param_subscribe_string (6.1), as :meth:`subscribe_int`.

        :param module: the CARMEN module name.
        :param variable: the variable within ``module``.
        :param target: ``(obj, 'attr')`` or ``(mapping, key)`` set to each new value; None: none.
        :param handler: called ``handler(module, variable, value)`` after the target is set.
        """
        self._subscribe(module, variable, ParamType.STRING, target, handler)

    def _on_event(self, event: ParameterEvent) -> None:
        self._received += 1
        if event.node != self.daemon:
            return
        for parameter in [*event.new_parameters, *event.changed_parameters]:
            for sub in self._subscriptions.get(parameter.name, ()):
                module, variable = parameter.name.split('.', 1)
                try:
                    value = convert(parameter_value_to_python(parameter.value), sub.kind,
                                    f'{module}_{variable}')
                except ParamTypeError as error:
                    print(f'WARNING: subscription ignores a change: {error}', file=sys.stderr,
                          flush=True)
                    continue
                assign(sub.target, value)
                if sub.handler is not None:
                    sub.handler(module, variable, value)

    def update(self, timeout: float = 0.0) -> int:
        """Apply the changes that arrived (targets, then handlers).  Call it once per loop turn
        of a program that subscribes.

        :param timeout: seconds to wait for the first event; 0: no waiting.
        :returns: how many parameter events were taken in (of any node: the daemon's only are
            applied); 0 before the first subscription.
        """
        if self._events is None or self._executor is None:
            return 0
        before = self._received
        self._executor.spin_once(timeout_sec=max(0.0, timeout))
        for _ in range(1000):
            seen = self._received
            self._executor.spin_once(timeout_sec=0.0)
            if self._received == seen:
                break
        return self._received - before

    # -- the parameter factory (6.2) and the command line (6.3) ---------------------------------
    def install_params(self, argv: Sequence[str], params: Sequence[Param]) -> list[str]:
        """carmen_param_install_params: load every parameter of ``params`` in one step into its
        target, and subscribe those marked so (6.2).  Call this before ``manager.parse_options``.

        :param argv: the command line, program name first.  ``-h``, ``-help`` or ``--help``
            prints :func:`param_table` and exits 0.  ``-VARIABLE VALUE`` (no module name, 6.3)
            overrides that parameter for this process; the daemon need not have it, and a
            subscribed one still follows later changes.  Everything from ``--ros-args`` on is
            left alone.
        :param params: the parameter factory's list.
        :returns: ``argv`` without the override pairs it took.

        :raises ParamExit: status 0 after ``-h``; status 1 naming the first parameter the daemon
            does not have (unless unfound variables are allowed) or whose value does not convert.
        """
        argv = list(argv)
        program = argv[0] if argv else 'program'
        if any(arg in ('-h', '-help', '--help') for arg in argv[1:]):
            print(param_table(program, params), flush=True)
            raise ParamExit(0, 'help')
        rest, overrides = self._overrides(argv, params)
        wanted = [f'{p.module}.{p.variable}' for p in params if p.name not in overrides]
        served = self._fetch(wanted) if wanted else {}
        for p in params:
            try:
                if p.name in overrides:
                    value = convert(overrides[p.name], p.type, p.name)
                elif f'{p.module}.{p.variable}' in served:
                    value = convert(served[f'{p.module}.{p.variable}'], p.type, p.name)
                elif self._allow_unfound:
                    continue
                else:
                    self._exit(f'{program}: the parameter server {self.daemon} has no definition '
                               f'for {p.name}, which this program needs')
            except ParamTypeError as error:
                self._exit(f'{program}: {error}')
            assign(p.target, value)
        for p in params:
            if p.subscribe:
                self._subscribe(p.module, p.variable, p.type, p.target, p.handler)
        return rest

    @staticmethod
    def _exit(message: str) -> None:
        print(message, file=sys.stderr, flush=True)
        raise ParamExit(1, message)

    @staticmethod
    def _overrides(argv: list[str], params: Sequence[Param]) -> tuple[list[str], dict[str, str]]:
        """6.3: ``-variable value`` pairs matched against the list's variable names (the first
        parameter of that variable name wins; the seed leaves duplicates undefined)."""
        by_variable: dict[str, Param] = {}
        for p in params:
            by_variable.setdefault(p.variable, p)
        rest, overrides = argv[:1], {}
        index = 1
        while index < len(argv):
            arg = argv[index]
            if arg == '--ros-args':
                rest += argv[index:]
                break
            found = by_variable.get(arg[1:]) if arg.startswith('-') else None
            if found is not None and index + 1 < len(argv):
                overrides[found.name] = argv[index + 1]
                index += 2
                continue
            rest.append(arg)
            index += 1
        return rest, overrides

    # -- changing the daemon's parameters (param_tool) ------------------------------------------
    def set_variable(self, name: str, value: Any) -> str:
        """carmen_param_set_variable: set a parameter on the daemon.

        :param name: ``module_variable``, or the variable after :meth:`set_module`.
        :param value: the new value; text is taken as the type the daemon serves when it reads as
            one (``"0.4"`` for a float, ``"on"`` or ``"true"`` for a bool).
        :returns: the value set, as CARMEN's text (on/off for a bool).

        :raises DaemonError: with the daemon's reason (undeclared, wrong type, read-only).
        """
        candidates = self._candidates(name)
        served = self._fetch(candidates)
        ros = next((n for n in candidates if n in served), candidates[0])
        if isinstance(value, str):
            value = as_served(value, served.get(ros))
        try:
            self._set(ros, value, name)
        except DaemonError as error:
            if ros in served:
                raise
            raise DaemonError(f'{name}: {self.daemon} has no such parameter; {error}') from None
        return text_of(value)

    def reread(self) -> None:
        """Ask the daemon to re-read its carmen.ini.

        :raises DaemonError: with the daemon's file:line: reason when it refuses the file.
        """
        self._set(REREAD, True, 'reread')

    def _set(self, ros: str, value: Any, label: str) -> None:
        self.open()
        assert self._client is not None
        client = self._client
        result = self._call(lambda: client.set_parameters([Parameter(ros, value=value)])).results[0]
        if not result.successful:
            raise DaemonError(f'{label}: {result.reason}')

