"""CommsManager: one per process; owns the ROS node and runs WURDE's loop (guide chapters 1, 5).

``run_update()`` publishes what is pending, takes in what arrived (draining subscriptions with
``take``, no executor), applies MCP and state commands, sends the heartbeat, waits for triggers
and sleeps per the rate settings, then returns the run state::

    while manager.run_update() == RunState.RUN:
        ...
    manager.clean_up()

Nothing blocks longer than asked: waits are sliced so that signals and state commands are seen
within :data:`WAIT_SLICE_S`.  ``step()`` is the deterministic single step for tests.

Run states (guide 5.2.1).  ``run_update()`` returns only RUN or QUIT, so the guide's loop is
correct as printed: the module lives through the MCP's other states, Idle (no data in or out),
Reset (forget what was taken in and not read) and Restart (re-execute the program in the same
process).  :meth:`CommsManager.on_state` callbacks run in the loop's thread and replace the
defaults of Reset and Restart; :meth:`CommsManager.set_return_states` hands the states to a loop
that interprets them itself.  docs/programming.md ("Programming with wurde_core") describes each state.

Before changing it: everything runs in the program's own thread (no executor: the node's services
are served from the loop), and a quitting module's clean-up must end in bounded time even when DDS
hangs in C
(:data:`SLOW_CLEANUP_DUMP_S`, :mod:`wurde_core.exit_timer`).
"""

from __future__ import annotations

import atexit
import faulthandler
import gc
import math
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

from rclpy.context import Context
from rclpy.node import Node

from . import cooperative, module_context
from . import options as _options
from .enums import ConnectionStrategy, RunState
from .errors import ConfigError, InvalidTypeError, InvalidValueError, OptionError, RegistrationError
from .exit_timer import ExitTimer
from .heartbeat import ModuleHeartbeat
from .mcp_client import McpClient
from .naming import stream_segment_path
from .robot_object import CONSUMER, SUPPLIER, RobotObject
from .role_config import DEFAULT_ROLE_CONFIG, RoleConfiguration, set_global_configuration
from .carmen_tunables import OPTION as DAEMON_OPTION
from .carmen_tunables import DaemonTunables, daemon_of
from .parameters import Check, Tunable, Tunables, declare_configuration
from .ros_adaptor import NodeEntities, SubscriptionWaiter, open_node
from .timestamp import Timestamp
from .trigger import Trigger

#: Longest single wait inside run_update, so that signals and commands are seen promptly.
WAIT_SLICE_S = 0.05
#: How long registration mode (-r) waits for an MCP to listen (discovery on a loaded machine can
#: take seconds).
REGISTRATION_WAIT_S = 10.0
#: Heartbeat TTL announced just before a Restart re-executes the program: long enough for the new
#: process to start and beat, so that the MCP does not take the gap for a hang.
RESTART_TTL_S = 30.0
#: Bound on waiting for the goodbye heartbeat to be acknowledged at clean-up.
GOODBYE_WAIT_S = 1.0
#: A quitting module's clean-up (goodbye, node and context shutdown, normally well under a second)
#: still running this long is stuck: every thread's traceback to stderr (faulthandler's "Timeout"
#: dump), then the process exits — with status 1 if it was in our own part (goodbye, daemon,
#: objects), with status 0 if it was in the DDS teardown of an exiting program
#: (``clean_up(exiting=True)``: the module had done all it owed, and Fast DDS's node deletion can
#: take past 2 s on a loaded machine).  A hang inside DDS runs no Python: both timers are C-level.
SLOW_CLEANUP_DUMP_S = 2.0
#: An abandoned DDS teardown's exit comes this long after its dump, for the dump to be written.
ABANDON_AFTER_DUMP_S = 0.2

StateCallback = Callable[[], None]


def _abandon_teardown_at(deadline: float) -> ExitTimer | None:
    """Bound an exiting module's DDS teardown by ``deadline`` (monotonic): faulthandler dumps
    every thread then — replacing the clean-up's dump-and-exit-1 timer, which bounds our own part
    — and the process exits 0 ABANDON_AFTER_DUMP_S later unless the teardown has returned and
    cancelled it.  C-level both: the teardown is one C call that may hold the GIL.  Without a
    POSIX timer (the system refuses one) the dump-and-exit-1 timer stays: None."""
    left = max(deadline - time.monotonic(), 0.001)
    try:
        timer = ExitTimer(left + ABANDON_AFTER_DUMP_S, 0)
    except OSError as error:
        print(f'wurde_core: no exit timer for the DDS teardown ({error})', file=sys.stderr, flush=True)
        return None
    faulthandler.dump_traceback_later(left, exit=False)
    return timer


def skip_final_collection() -> None:
    """Spare an ending program the interpreter's last garbage collection: ``gc.freeze`` moves
    every object into the generation collections never visit, so the finalization frees them by
    reference counts only.  A module's last collection walks every object of rclpy, numpy and
    its own (about 0.1 s of CPU, 60 % of its exit); every module of an MCP stopping at once on a
    loaded machine paid it together, and ended 2 s after the Quit.  What the collection would
    still run, ``__del__`` of objects in reference cycles, Python does not promise at exit
    either; the module's device, log file and DDS entities are closed before this.  For a
    program that ends right after it (a module's clean-up, a container's end)."""
    gc.freeze()


class CommsManager:
    """The communication manager of one module (process)."""

    def __init__(self, name: str, *, node_type: type[Node] = Node) -> None:
        """The manager of the module ``name``; its node is created at the first registration.

        :param name: the module's name: its node's (written as a stream segment when it is not a
            plain ROS name) and its heartbeat stream's (``heartbeat/<name>``); ``-n`` in
            :meth:`parse_options` replaces it.
        :param node_type: the rclpy node class to create (a LifecycleNode subclass for the MCP:
            one node per module, whose services the manager's loop serves).
        :raises InvalidValueError: for an empty ``name``.
        """
        if not name:
            raise InvalidValueError('a CommsManager needs the module name')
        self.name = name
        self.state = RunState.RUN
        self.options = _options.Options()
        self.config = RoleConfiguration(name)
        self.node: Any = None
        self._node_type = node_type
        self._context: Context | None = None
        self._help = ''
        self._user_spec: str | None = None
        self._sleep_s = 0.1
        self._ttl_s = 0.2
        self._sleep_enabled = True
        self._pre_sleep = False
        self._heartbeat_enabled = True
        self._trust_ttl = False
        self._quit_time = 0.0
        self._return_states = False
        self._objects: list[RobotObject] = []
        self._system_objects: list[RobotObject] = []
        self._triggers: list[Trigger] = []
        self._heartbeat: ModuleHeartbeat | None = None
        self._mcp: McpClient | None = None
        self._closed = False
        self._started = False
        self._waiters: dict[bool, SubscriptionWaiter] = {}
        self._tunables = Tunables()
        self._daemon: DaemonTunables | None = None
        self._entities: NodeEntities | None = None
        self._previous_handlers: dict[int, Any] = {}
        self._signals = 0
        self._told_to_quit = False
        self._hooks: dict[RunState, list[StateCallback]] = {}
        self._entered: list[RunState] = []
        # From here on SIGINT/SIGTERM mean Quit, also while the node is being created (seconds on
        # a loaded machine: a module stopped then must still end cleanly, not by KeyboardInterrupt).
        self._install_signal_handlers()
        # In a container (issue 39) the container stands for the process: it tells the module to
        # quit instead of a signal, and owns the rclpy context and the process's exit.
        self._contained = module_context.current()
        if self._contained is not None:
            with self._contained.lock:
                self._contained.manager = self
                if self._contained.quit_requested:
                    self.state = RunState.QUIT

    @property
    def context(self) -> Context | None:
        """The rclpy context of this module's node (``None`` before the first registration or
        update), for code that adds its own executor or entities to the node."""
        return self._context

    # -- options (guide 5.1.1) -----------------------------------------------------------------
    def set_help_string(self, text: str) -> None:
        """Extra text for ``-h``.

        :param text: printed after the standard usage lines.
        """
        self._help = text

    def parse_options(self, argv: Sequence[str], user_spec: str | None = None) -> _options.Options:
        """Parse the standard options and ``user_spec``, and load the role configuration.

        ``-h`` prints help and exits 0; a wrong option or an unreadable role-config prints the
        reason and usage on stderr and exits with status 2.  The configuration read (``-g FILE``,
        else ``role-config.xml`` when the working directory has one) becomes the global one, with
        the user options set in it.

        :param argv: the command line, program name first (``sys.argv``); ``--ros-args ...`` is
            kept for the node.
        :param user_spec: the program's own options in getopt form (``"c:ab"``: ``-c`` takes a
            value, ``-a`` and ``-b`` do not and read ``"true"`` when given); None for none.  A
            letter of a standard option is refused.
        :returns: the options found.
        """
        argv = list(argv)
        program = os.path.basename(argv[0]) if argv else self.name
        try:
            opts = _options.parse(argv[1:], user_spec)
        except OptionError as exc:
            print(f'{program}: {exc}\n{_options.usage(program, self.name, user_spec, self._help)}',
                  file=sys.stderr)
            sys.exit(2)
        if opts.help:
            print(_options.usage(program, self.name, user_spec, self._help))
            sys.exit(0)
        if opts.name:
            self.name = opts.name
        config = RoleConfiguration(self.name)
        path = opts.config_file or (DEFAULT_ROLE_CONFIG if os.path.exists(DEFAULT_ROLE_CONFIG)
                                    else None)
        if path:
            try:
                config.load(path)
            except ConfigError as exc:
                print(f'{program}: {exc}', file=sys.stderr)
                sys.exit(2)
        for letter, value in opts.user.items():
            config.set_option(letter, value)
        self.config = config
        set_global_configuration(config)
        self.options = opts
        self._user_spec = user_spec
        return opts

    def tunable(self, name: str, default: bool | int | float | str, description: str,
                minimum: float | None = None, maximum: float | None = None) -> Tunable:
        """A value this module lets users change while it runs: a writable ROS 2 parameter of
        its node (``ros2 param set``, ``--params-file``); read it as ``.value`` where it is used.
        The WURDE options and configuration are parameters too, read-only
        (:mod:`wurde_core.parameters`).

        :param name: the parameter's name, not starting with ``wurde.``.
        :param default: the value until a user sets one; its type (bool, int, float or str) is
            the parameter's.
        :param description: the parameter descriptor's text (``ros2 param describe``).
        :param minimum: the lowest value taken, for a number; None: no bound.
        :param maximum: the highest value taken, for a number; None: no bound.
        :raises ValueError: for a name declared twice or inside ``wurde.``.
        :raises TypeError: for a bound on a value that is not a number.
        """
        return self._tunables.declare(name, default, description, minimum, maximum)

    def check_tunables(self, check: Check) -> None:
        """Refuse new tunable values that ``check`` finds wrong, with its reason, before any is
        taken.

        :param check: called with ``{name: value}`` of the tunables being set; returns the reason
            to refuse them, or None to accept.
        """
        self._tunables.add_check(check)

    # -- rate and heartbeat (guide 5.2) --------------------------------------------------------
    def set_sleep(self, seconds: float) -> None:
        """Sleep ``seconds`` per loop; the heartbeat TTL becomes twice that.

        :param seconds: the sleep of each ``run_update`` (default 0.1 s).
        """
        self._sleep_s = float(seconds)
        self._ttl_s = 2 * float(seconds)
        self._sleep_enabled = True

    def set_sleep_only(self, seconds: float) -> None:
        """Sleep ``seconds`` per loop without changing the heartbeat TTL.

        :param seconds: the sleep of each ``run_update``.
        """
        self._sleep_s = float(seconds)
        self._sleep_enabled = True

    def set_no_sleep(self) -> None:
        """No rate control: run_update returns as soon as it has done its work."""
        self._sleep_enabled = False

    def set_pre_sleep(self) -> None:
        """Sleep before exchanging data."""
        self._pre_sleep = True

    def set_post_sleep(self) -> None:
        """Sleep after exchanging data (the default)."""
        self._pre_sleep = False

    def set_heartbeat_only(self, ttl: float, *, trust: bool = False) -> None:
        """Set the heartbeat TTL without changing the sleep (the guide's setHeartbeatOnly, 6.1),
        and turn the heartbeat on.

        :param ttl: seconds the MCP waits for the next beat.  The MCP clamps it to 1-10 s unless
            ``trust`` is set.
        :param trust: the MCP waits up to the announced TTL (at most 300 s): for a loop that may
            really stay away that long (a long computation between two ``run_update`` calls).
        """
        self._ttl_s = float(ttl)
        self._heartbeat_enabled = True
        if trust != self._trust_ttl:
            self._trust_ttl = trust
            self._describe()

    def set_quit_time(self, seconds: float) -> None:
        """Tell the MCP how long this module may take to end after a Quit (work it owes before
        exiting, as Pluto's slamModule saves its map when stopped, Pluto 7.2: "one should wait").

        :param seconds: the MCP waits that long (at most 120 s) before its signals; 0: the MCP's
            default grace of about 2 s.
        :raises InvalidValueError: for a negative or non-finite number.
        """
        if not math.isfinite(seconds) or seconds < 0:
            raise InvalidValueError(f'a quit time is a number of seconds >= 0, not {seconds!r}')
        if float(seconds) != self._quit_time:
            self._quit_time = float(seconds)
            self._describe()

    def set_no_heartbeat(self) -> None:
        """Send no heartbeat (the MCP will not watch this module)."""
        self._heartbeat_enabled = False

    def heartbeat_enabled(self) -> bool:
        """Whether this module sends a heartbeat (see :meth:`set_no_heartbeat`)."""
        return self._heartbeat_enabled

    def ttl(self) -> float:
        """Current heartbeat TTL in seconds."""
        return self._ttl_s

    def sleep_time(self) -> float:
        """Seconds slept in each ``run_update`` (0 after :meth:`set_no_sleep`)."""
        return self._sleep_s if self._sleep_enabled else 0.0

    # -- registration --------------------------------------------------------------------------
    def register_supplier(self, obj: RobotObject) -> None:
        """Make ``obj`` a supplier: it sends data and info, receives requests.  The first
        registration creates the node.

        :param obj: an object of an interface class, not yet registered; its stream is the name
            it was made with.
        :raises RegistrationError: when ``obj`` is already registered, or the manager was cleaned
            up.
        :raises InvalidTypeError: when ``obj`` is not a RobotObject.
        """
        self._register(obj, SUPPLIER)

    def register_consumer(self, obj: RobotObject) -> None:
        """Make ``obj`` a consumer: it receives data and info, sends requests.  An ASSIGNED or
        AUTO object asks the MCP for its stream and connects when it answers; a NORMAL one
        connects at once and asks the MCP to start its supplier.

        :param obj: an object of an interface class, not yet registered.
        :raises RegistrationError: when ``obj`` is already registered, or the manager was cleaned
            up.
        :raises InvalidTypeError: when ``obj`` is not a RobotObject.
        """
        self._register(obj, CONSUMER)

    def register_trigger(self, trigger: Trigger) -> None:
        """``run_update`` will return only when this (or another registered) trigger fires.

        :param trigger: registered once; registering it again changes nothing.
        """
        if trigger not in self._triggers:
            self._triggers.append(trigger)

    def triggers(self) -> list[Trigger]:
        """The registered triggers."""
        return list(self._triggers)

    def unregister_trigger(self, trigger: Trigger) -> None:
        """Stop ``run_update`` waiting for ``trigger``.

        :param trigger: a registered trigger (one that is not is ignored).
        """
        self._triggers = [t for t in self._triggers if t is not trigger]

    def objects(self, user_only: bool = False) -> list[RobotObject]:
        """Registered objects.

        :param user_only: only the program's; False adds the manager's own (heartbeat, MCP
            requests).
        """
        return list(self._objects) if user_only else list(self._objects + self._system_objects)

    def _register(self, obj: RobotObject, role: str) -> None:
        if not isinstance(obj, RobotObject):
            raise InvalidTypeError(f'{obj!r} is not a RobotObject')
        if obj.role is not None:
            where = 'this' if obj._manager is self else 'another'
            raise RegistrationError(f'{obj._label()} is already registered as a {obj.role} with '
                                    f'{where} CommsManager; register each object once')
        self._open()
        obj._register(self, role)
        self._objects.append(obj)
        if role == CONSUMER and obj.strategy in (ConnectionStrategy.ASSIGNED,
                                                 ConnectionStrategy.AUTO):
            self._mcp_client().request_stream(obj)
        else:
            obj._connect(obj.stream or obj.object_name)
            if obj.strategy == ConnectionStrategy.NORMAL and role == CONSUMER:
                self._mcp_client().request_start(obj)
        self.entities_changed()

    def unregister(self, obj: RobotObject) -> None:
        """Release ``obj``'s stream and forget it (it may be registered again afterwards); it
        also leaves every trigger.

        :param obj: an object registered with this manager.
        :raises RegistrationError: when ``obj`` is not registered with this manager.
        """
        if not any(o is obj for o in self._objects):
            raise RegistrationError(f'{obj._label()} is not registered with CommsManager '
                                    f'"{self.name}"')
        if self._mcp is not None:
            self._mcp.forget(obj)
        obj._disconnect()
        obj._unregister()
        self._objects = [o for o in self._objects if o is not obj]
        for trigger in self._triggers:
            trigger.remove(obj)
        self.entities_changed()

    def entities_changed(self) -> None:
        """An object's publishers or subscriptions changed (registration, assignment, a queue
        mode switched after connection): wait anew, and tell the MCP if it cares."""
        self._waiters.clear()
        if self._started:
            self._describe()

    def _connect_assigned(self, obj: RobotObject, stream: str) -> None:
        """The MCP assigned ``stream`` to a waiting object."""
        if obj.is_connected():
            obj._disconnect()
        obj._connect(stream)
        self.entities_changed()

    def _register_system(self, obj: RobotObject, role: str) -> None:
        obj._register(self, role)
        obj._connect(obj.stream or obj.object_name)
        self._system_objects.append(obj)
        self._waiters.clear()

    def _mcp_client(self) -> McpClient:
        if self._mcp is None:
            self._mcp = McpClient(self.name, self.log_warning)
            self._register_system(self._mcp.obj, CONSUMER)
        return self._mcp

    def _describe(self) -> None:
        if self._heartbeat is not None and self.node is not None:
            self._heartbeat.describe(self.state, self._objects, trust_ttl=self._trust_ttl,
                                     quit_time=self._quit_time)

    # -- life cycle ----------------------------------------------------------------------------
    def _open(self) -> None:
        """Create the ROS node (once); called by the first registration or update."""
        if self.node is not None:
            return
        if self._closed:
            raise RegistrationError(f'CommsManager "{self.name}" was cleaned up')
        stream_segment_path(self.name)  # refuses names that can not be a stream segment
        node_name = stream_segment_path(self.name).replace('/', '_')
        self._context, self.node = open_node(node_name, self.options.ros_arguments,
                                             self._node_type)
        if self._contained is None:
            atexit.register(self.clean_up)
        declare_configuration(self.node, self.name, self.config)
        self._tunables.attach(self.node)
        self._entities = NodeEntities(self.node)
        if self._heartbeat_enabled:
            self._heartbeat = ModuleHeartbeat(self.name)
            self._register_system(self._heartbeat.obj, SUPPLIER)

    def _install_signal_handlers(self) -> None:
        if threading.current_thread() is not threading.main_thread() or self._previous_handlers:
            return
        for signum in (signal.SIGINT, signal.SIGTERM):
            self._previous_handlers[signum] = signal.signal(signum, self._on_signal)
        # A SIGTERM writes every thread's traceback to stderr (the MCP's module log) as it comes,
        # from faulthandler's C handler, then goes on to ours: the MCP sends it 3 s into a Quit
        # that has not ended, 1 s before its SIGKILL, so the log says where the exit was stuck —
        # also when the main thread is held in C and runs no Python handler (a module SIGKILLed
        # there would otherwise leave nothing in its log).  Not on SIGINT: a user's Ctrl-C may
        # rightly be followed by seconds of work (a mission's summary).
        try:
            faulthandler.register(signal.SIGTERM, all_threads=True, chain=True)
        except (ValueError, RuntimeError, AttributeError):      # no usable stderr
            pass

    def _on_signal(self, signum: int, _frame: Any) -> None:
        self._signals += 1
        if self._signals > 1 and signum == signal.SIGINT:
            raise KeyboardInterrupt
        self.state = RunState.QUIT

    def request_quit(self) -> None:
        """Quit, as SIGINT or SIGTERM asks a module process to (from any thread: a container
        tells its module so, :mod:`.module_context`)."""
        self._signals += 1
        self.state = RunState.QUIT

    def _start(self) -> None:
        """First update: registration and capability listing (-r, -l), process description."""
        self._started = True
        if self.options.registration or self.options.list_capabilities:
            reached = self._mcp_client().report_capabilities(self._objects, REGISTRATION_WAIT_S)
            caps = McpClient.capabilities(self._objects)
            for interface, stream in caps['supplies']:
                print(f'supplies {interface} {stream}')
            for interface, alias in caps['consumes']:
                print(f'consumes {interface} {alias}')
            print(f'capabilities of {self.name} {"sent to" if reached else "not received by"} '
                  'the MCP', flush=True)
            if self.options.registration:
                self.state = RunState.QUIT
        self._follow_daemon()
        self._describe()

    def _follow_daemon(self) -> None:
        """With the role configuration's ``param_daemon`` option (the module's own, else the
        global one), the tunables follow CARMEN's parameter daemon (:mod:`.carmen_tunables`)."""
        if self.config.have_module_option(self.name, DAEMON_OPTION):
            value = self.config.get_module_option(self.name, DAEMON_OPTION)
        else:
            value = self.config.get_option(DAEMON_OPTION)
        daemon = daemon_of(value)
        if daemon and self._tunables.items() and self.state != RunState.QUIT:
            self._daemon = DaemonTunables(self, self._tunables, daemon, self.log_warning)

    # -- run states (guide 5.2.1) ----------------------------------------------------------------
    def on_state(self, state: RunState, callback: StateCallback) -> None:
        """Call ``callback()`` in the loop's thread when this module enters ``state``.

        :param state: IDLE, RESET, RESTART, or RUN (on returning from another state).  A callback
            for RESET or RESTART replaces the default; the module returns to Run after it unless
            it chose another state.
        :param callback: called with no arguments; several for one state run in order.
        :raises InvalidValueError: for QUIT (act on it after ``run_update`` returns QUIT).
        """
        state = RunState(state)
        if state == RunState.QUIT:
            raise InvalidValueError('Quit ends the loop; act on it after run_update returns QUIT')
        self._hooks.setdefault(state, []).append(callback)

    def set_return_states(self, enabled: bool = True) -> None:
        """Let ``run_update`` return Idle, Reset and Restart to the program's loop, as the guide's
        main loop interprets them (5.2.1): each call in such a state is one turn on the heartbeat
        and MCP channels only (no data in or out) and returns the state, until the MCP sets
        another or the program calls :meth:`set_run`.  ``on_state`` callbacks for Reset and
        Restart still handle those states instead; no defaults run.

        :param enabled: True to return the states; False for the default (only RUN or QUIT).
        """
        self._return_states = enabled

    def set_run(self) -> None:
        """Return to Run after handling Idle, Reset or Restart."""
        self._change_state(RunState.RUN)

    def set_state(self, state: RunState) -> None:
        """Change this module's own run state (as a command from the MCP would).

        :param state: the new state; the heartbeat (when the module has one) tells the MCP at
            once.
        """
        self._change_state(RunState(state))

    def _change_state(self, state: RunState) -> None:
        if state == self.state:
            return
        self.state = state
        self._entered.append(state)
        if self._heartbeat is not None and self.node is not None:
            self._describe()
            self._heartbeat.beat(self._ttl_s, force=True)

    def _dispatch(self) -> None:
        """Run the callbacks of the states entered since the last dispatch, in order."""
        while self._entered:
            state = self._entered.pop(0)
            for callback in self._hooks.get(state, ()):
                callback()

    def _settle(self, *, block: bool = True) -> None:
        """Handle Idle, Reset and Restart until the state is Run or Quit (``block=False``: one
        turn of Idle at most, for :meth:`step`)."""
        while True:
            self._dispatch()
            state = self.state
            if state in (RunState.RUN, RunState.QUIT):
                return
            if self._return_states and (state == RunState.IDLE or not self._hooks.get(state)):
                return                                  # the program's loop handles it
            if state == RunState.IDLE:
                self._idle_turn()
                if not block:
                    return
            elif state in (RunState.RESET, RunState.RESTART):
                if not self._hooks.get(state):
                    (self._default_reset if state == RunState.RESET else self._default_restart)()
                if self.state == state:
                    self._change_state(RunState.RUN)

    def _idle_turn(self) -> None:
        """One turn of Idle: sleep on the heartbeat and MCP channels, take their traffic in,
        beat.  No data in or out."""
        slice_s = WAIT_SLICE_S
        if self._heartbeat is not None and self._heartbeat_enabled:
            slice_s = min(slice_s, max(self._heartbeat.next_beat_in(self._ttl_s), 0.001))
        self._wait_once(slice_s, system_only=True)
        self._exchange()
        self._beat()

    def _default_reset(self) -> None:
        """Forget what was taken in and not yet read: it belonged to the state before."""
        for obj in self._objects:
            obj._discard_pending()

    def _default_restart(self) -> None:
        """Start this program again in the same process (same PID, fresh state)."""
        if self._heartbeat is not None and self.node is not None:
            self._heartbeat.beat(RESTART_TTL_S, force=True)
            self._heartbeat.obj.wait_delivered(GOODBYE_WAIT_S, channel='data')
        self.clean_up(goodbye=False)
        sys.stdout.flush()
        sys.stderr.flush()
        os.execv(sys.executable, [sys.executable, *sys.orig_argv[1:]])

    def run_update(self, timeout: float | None = None) -> RunState:
        """One turn of the module's loop; returns the run state (RUN or QUIT, unless
        :meth:`set_return_states`).  Sleeps per the rate settings.

        :param timeout: with triggers registered, the longest wait in seconds for one to fire;
            None: no limit (it still returns when the state changes).  Unused without triggers.
        """
        self._open()
        if not self._started:
            self._start()
        self._settle()
        if self.state == RunState.QUIT:
            return self.state
        if self.state != RunState.RUN:                  # set_return_states: the loop's to handle
            self._idle_turn()
            self._settle()
            return self.state
        if self._sleep_enabled and self._pre_sleep:
            self._nap(self._sleep_s)
        self._exchange()
        if self._triggers and self.state == RunState.RUN:
            self._wait_for_trigger(timeout)
        self._beat()
        if self._sleep_enabled and not self._pre_sleep:
            self._nap(self._sleep_s)
        self._settle()
        return self.state

    def step(self) -> RunState:
        """Deterministic single step: exchange and heartbeat, no sleeping and no waiting beyond
        one Idle turn; returns the state, which may be IDLE."""
        self._open()
        if not self._started:
            self._start()
        self._exchange()
        self._beat()
        self._settle(block=False)
        return self.state

    def wait(self, timeout: float) -> bool:
        """Block until something arrives on any stream of this module or ``timeout`` passes.

        For programs that wait between steps without triggers.  What arrived is taken in by the
        next ``run_update`` or ``step``.

        :param timeout: the longest wait, in seconds.
        :returns: whether something arrived (False at once in the QUIT state).
        """
        self._open()
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or self.state == RunState.QUIT:
                return False
            if self._wait_once(min(remaining, WAIT_SLICE_S)):
                return True

    def _wait_for_trigger(self, timeout: float | None) -> None:
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.state == RunState.RUN:
            if any(trigger.fire() for trigger in self._triggers):
                return
            slice_s = WAIT_SLICE_S
            if self._heartbeat is not None and self._heartbeat_enabled:
                slice_s = min(slice_s, max(self._heartbeat.next_beat_in(self._ttl_s), 0.001))
            if deadline is not None:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return
                slice_s = min(slice_s, remaining)
            self._wait_once(slice_s)
            self._exchange()
            self._beat()

    def _waiter(self, system_only: bool) -> SubscriptionWaiter:
        waiter = self._waiters.get(system_only)
        if waiter is None:
            objects = self._system_objects if system_only else self._objects + self._system_objects
            entities, context = self._entities, self._context
            assert entities is not None and context is not None  # both set by _open
            waiter = SubscriptionWaiter(context,
                                        [s for o in objects for s in o._subscriptions()]
                                        + entities.subscriptions, entities.services)
            self._waiters[system_only] = waiter
        return waiter

    def _wait_once(self, seconds: float, *, system_only: bool = False) -> bool:
        return self._waiter(system_only).wait(seconds)

    def _exchange(self) -> None:
        """Take in what arrived: the manager's own channels always, the program's only in Run.
        Only the subscriptions a wait set poll finds holding something are taken from."""
        ready = self._waiter(self.state != RunState.RUN).ready()
        assert self._entities is not None
        if self._entities.serve(ready):  # parameters (in Idle too), and rclpy's /clock
            self._entities = NodeEntities(self.node)
            self._waiters.clear()
        for obj in self._system_objects:
            obj._drain(ready)
        if self._heartbeat is not None:
            for state in self._heartbeat.commands():
                self._change_state(state)
                # Told to quit: whoever told us already knows, so the goodbye need not wait
                # for their acknowledgement (clean_up).
                self._told_to_quit = state == RunState.QUIT
        if self._mcp is not None:
            for obj, stream in self._mcp.poll():
                self._connect_assigned(obj, stream)
        if self.state == RunState.RUN:
            for obj in self._objects:
                obj._drain(ready)
        if self._daemon is not None:
            self._daemon.poll()

    def _beat(self) -> None:
        if self._heartbeat is not None and self._heartbeat_enabled:
            self._heartbeat.beat(self._ttl_s)

    def _nap(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while self.state != RunState.QUIT:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return
            cooperative.sleep(min(remaining, WAIT_SLICE_S))

    def clean_up(self, *, goodbye: bool = True, wait: bool = True, exiting: bool = False) -> None:
        """Say goodbye to the MCP and release everything; idempotent, also run at exit.

        :param goodbye: announce the Quit state on the heartbeat first; False for a Restart.
        :param wait: wait (at most :data:`GOODBYE_WAIT_S`) for the goodbye to be acknowledged,
            unless the Quit was commanded.  False is the MCP's own: its readers are mostly the
            modules it has just ended, which a loaded machine's DDS still counts for a while.
        :param exiting: the program ends right after (a module's main): a quitting module whose
            goodbye is sent and whose own resources are released then gives the DDS teardown
            until :data:`SLOW_CLEANUP_DUMP_S` from the start, and if it is still running, dumps
            every thread (where it was) and exits with status 0, abandoning it to the kernel.
        """
        if self._closed:
            return
        self._closed = True
        ending = self.state == RunState.QUIT
        deadline = time.monotonic() + SLOW_CLEANUP_DUMP_S
        # A contained module shares the process: no exit timers, and the context is the container's.
        process_wide = self._contained is None
        if ending and process_wide:
            faulthandler.dump_traceback_later(SLOW_CLEANUP_DUMP_S, exit=True)
        abandon = None
        if self.node is not None:
            try:
                if self._heartbeat is not None and goodbye:
                    self.state = RunState.QUIT
                    self._describe()
                    # Let the goodbye reach the MCP before the writer disappears (bounded) —
                    # unless the MCP (or a controller) commanded the Quit: it knows, and waits for
                    # the exit.  A reliable writer's acknowledgements can take the DDS heartbeat
                    # period, and every module of an MCP stopping at once must end in seconds.
                    if wait and not self._quit_was_commanded():
                        self._heartbeat.obj.wait_delivered(GOODBYE_WAIT_S, channel='info')
                if self._daemon is not None:
                    self._daemon.close()
                for obj in self._objects + self._system_objects:
                    obj._disconnect()
                if ending and exiting and process_wide:
                    abandon = _abandon_teardown_at(deadline)
                self.node.destroy_node()
            finally:
                if self._context is not None and process_wide:
                    self._context.try_shutdown()
                if abandon is not None:
                    abandon.cancel()
        if self._previous_handlers:
            faulthandler.unregister(signal.SIGTERM)
        for signum, handler in self._previous_handlers.items():
            # A module that quit (told to, or by a signal) is on its way out: a SIGINT/SIGTERM
            # now (the MCP escalating because the exit is slow on a loaded machine) must not turn
            # a clean exit into a KeyboardInterrupt or a death by the signal.  SIG_IGN, not a
            # Python handler: the interpreter's finalization resets Python handlers to SIG_DFL
            # (and so would die of the signal) but leaves SIG_IGN alone.  SIGKILL still ends it.
            # Otherwise the program goes on: restore what was there.
            signal.signal(signum, signal.SIG_IGN if ending else handler)
        self._previous_handlers.clear()
        atexit.unregister(self.clean_up)
        if ending and process_wide:
            faulthandler.cancel_dump_traceback_later()
            if exiting:
                skip_final_collection()

    def _quit_was_commanded(self) -> bool:
        """Whether a Quit command came, also one still waiting in the heartbeat's reader: a
        module whose step ran long (a loaded machine) sees the MCP's SIGINT, 2 s after its Quit,
        before it looks at the command, and must not then wait for the MCP to acknowledge a
        goodbye it is not listening for — that wait can outlast the escalation's SIGKILL."""
        if not self._told_to_quit and self._heartbeat is not None:
            self._heartbeat.obj._drain()
            self._told_to_quit = RunState.QUIT in self._heartbeat.commands()
        return self._told_to_quit

    # -- time ----------------------------------------------------------------------------------
    def now(self) -> Timestamp:
        """The module's time, which auto-timestamps use: the ROS clock of its node — the wall
        clock, or the simulator's ``/clock`` when the node's ``use_sim_time`` is true (0 until
        the first ``/clock`` message, as in any ROS 2 node).  Loop rates, heartbeats and the
        MCP's TTLs stay on the machine's monotonic clock: they are about processes, not about
        the simulated world."""
        if self.node is None:
            return Timestamp.now()
        return Timestamp(microseconds=self.node.get_clock().now().nanoseconds // 1000)

    # -- logging helpers -----------------------------------------------------------------------
    def log_warning(self, text: str) -> None:
        """Warn through the global logger (stderr when there is none).

        :param text: the warning, prefixed with the module's name.
        """
        from .logger import g_warn
        g_warn(f'{self.name}: {text}')
