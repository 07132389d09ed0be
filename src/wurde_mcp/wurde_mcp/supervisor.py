"""The MCP's supervision: start modules, watch heartbeats and exits, restart, idle, assign.

Seed: WURDE Programming Guide 5.2.1 (heartbeat, states), 6.1 (locale, managed / unmanaged /
critical), 6.3 (stream selection).  :meth:`Supervisor.tick` is called from the MCP's WURDE loop;
nothing in it blocks: every slow action on a process (stop escalation, reaping, closing its log)
belongs to that process's owner thread (:mod:`wurde_mcp.process`), and the loop only reads what
the owner recorded.  Silence is judged on the supervision clock (:mod:`wurde_mcp.clock`), so the
MCP's own lag on a loaded machine never makes a module a zombie.  Exits and zombies are logged
with the monotonic time at which supervision saw them, so reaction times can be measured with
the MCP's own timestamps.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from typing import Any

from wurde_core import (CommsManager, ProcessLocale, ProcessType, RunState,
                        StatusMode, g_error, g_info, g_warn)
from wurde_core.heartbeat import MANAGED_ENV, MCP_ENV, RESTART_ENV
from wurde_core.interfaces import robot_object_class
from wurde_core.mcp_client import control_stream, mcp_stream
from wurde_core.resume import STATE_ENV

from .binaries import find_binary
from .clock import REVIEW_S, SupervisionClock
from .config import McpConfig, ModuleSpec
from .container.member import CONTAINER_BINARY, ContainedProcess, Container
from .process import ModuleProcess
from .progress import process_state, where_threads_wait
from .streams import StreamDesk

#: Restart delays by restart count (s); the last repeats until the cap.
BACKOFF_S = (0.0, 0.5, 1.0, 2.0, 4.0)
#: Least time between two state commands to a module that does not report the state it was told.
RECOMMAND_S = 1.0
#: How often a module told to Quit at the MCP's end is told again while it runs (s).
QUIT_REPEAT_S = 0.25
#: How long a module whose command channel has no reader yet is waited for at the MCP's end while
#: its process makes no progress (asleep, no CPU used), before its stop escalation starts without
#: a Quit it could hear (s).  One still starting (runnable or using CPU) is waited for until it can
#: hear, up to :data:`START_TIMEOUT_S` from its start, when the MCP would take it as hung anyway.
DEAF_WAIT_S = 5.0
#: Restarts of one module within :data:`RESTART_WINDOW_S` before the MCP gives up on it: a module
#: that keeps failing at once is given up on, one that dies now and then in a long run never is.
MAX_RESTARTS = 5
RESTART_WINDOW_S = 60.0
#: TTLs outside this range are not trusted (a module announcing 0 or a day is clamped).  The floor
#: keeps a busy machine from turning every briefly descheduled module into a "zombie": a loaded
#: machine can keep a healthy module with the guide's 0.2 s TTL (set_sleep(0.1)) silent for over
#: 0.3 s; a beat still comes at least every 0.1 s, so the floor only delays the verdict on a
#: module that really hangs.
TTL_RANGE_S = (1.0, 10.0)
#: The ceiling for a module that asks to be trusted (its heartbeat info's ``trust_ttl``,
#: ``CommsManager.set_heartbeat_only(ttl, trust=True)``): guide 6.1's TTL is how long the MCP
#: waits, and a loop may really stay away longer than 10 s; five minutes bounds a typo.
TRUSTED_TTL_MAX_S = 300.0
#: Slack on top of the TTL before a silent module is a zombie.
TTL_GRACE_S = 0.05
#: A module silent past its TTL whose process is runnable or uses CPU is starved, not hung
#: (:mod:`wurde_mcp.progress`): it is a zombie only when silent this many TTLs.
HARD_TTLS = 4.0
#: A silent module asleep and using no CPU for this long is hung (s; CPU time is counted in
#: 10 ms ticks, and a healthy module's loop uses more than one tick a second).
NO_PROGRESS_S = 1.0
#: A started module that has not sent its first heartbeat by then is taken as hung.
START_TIMEOUT_S = 30.0
#: How often the module table is published (s), besides on every change.
TABLE_PERIOD_S = 0.5
#: Stopping a module: wait this long for it to obey Quit, then SIGINT, SIGTERM, SIGKILL this far
#: apart.
STOP_GRACE_S, STOP_STEP_S = 2.0, 1.0
#: The longest quit time a module may ask for (its heartbeat info's ``quit_time``,
#: ``CommsManager.set_quit_time``): work owed before the exit, as a slamModule saving its map.
QUIT_TIME_MAX_S = 120.0
CMD_QUIT_ALL, CMD_START, CMD_STOP, CMD_RESTART, CMD_STATE = 1, 2, 3, 4, 5


@dataclass
class Module:
    """What the MCP knows of one module."""

    spec: ModuleSpec
    heartbeat: Any
    status: StatusMode = StatusMode.UNKNOWN
    process: ModuleProcess | ContainedProcess | None = None
    wanted: bool = False
    #: Supervision-clock time of the last beat (TTLs are judged on it), and monotonic time.
    last_beat: float | None = None
    last_beat_at: float | None = None
    ttl: float = 1.0
    run_state: RunState = RunState.RUN
    pid: int = 0
    host: str = ''
    restarts: int = 0
    #: Monotonic times of the automatic restarts within the last :data:`RESTART_WINDOW_S`.
    recent_restarts: list[float] = field(default_factory=list)
    #: Processes started for it so far (the next one learns it through :data:`RESTART_ENV`).
    starts: int = 0
    restart_at: float | None = None
    supplies: list[tuple[str, str]] = field(default_factory=list)
    consumes: list[tuple[str, str]] = field(default_factory=list)
    #: Start again as soon as the current process has ended (a restart or a start asked for
    #: while a stop was under way).
    start_on_exit: bool = False
    ever_active: bool = False
    #: The run state the MCP last commanded (Run or Idle are held: see Supervisor._reconcile),
    #: and when it last sent a state command (monotonic).
    commanded_state: RunState = RunState.RUN
    commanded_at: float = 0.0
    #: Silent past its TTL by the wall clock since its last beat (what the old rule judged).
    wall_late: bool = False
    #: While silent past its TTL: since when (monotonic) its process has made no progress, and
    #: its CPU time then (None: not overdue, or not looked at yet).
    stalled_at: float | None = None
    stalled_cpu: float = 0.0
    #: Pids of this module's processes that have ended: their heartbeats, still arriving after
    #: the exit (a loaded machine delivers late), are not the new process's.
    dead_pids: set[int] = field(default_factory=set)
    #: The running process has described itself (a heartbeat info not from a dead pid) since it
    #: was started: only then do its beats make it alive.
    described: bool = True
    #: The MCP the module says it belongs to (its heartbeat info; empty: none named or not heard
    #: yet).
    owner: str = ''
    #: The TTL its last beat announced, and whether it asks for it to be trusted beyond
    #: :data:`TTL_RANGE_S` (its heartbeat info); :attr:`ttl` is what the MCP makes of them.
    announced_ttl: float = 1.0
    trust_ttl: bool = False
    #: How long it may take to end after Quit (its heartbeat info; 0: :data:`STOP_GRACE_S`).
    quit_time: float = 0.0

    def quit_grace(self, default_s: float = STOP_GRACE_S) -> float:
        """The wait between a Quit and the first signal: the module's quit time, within
        :data:`QUIT_TIME_MAX_S`, or ``default_s``.

        :param default_s: the least wait (s), and the wait of a module that asked for none.
        """
        asked = self.quit_time if math.isfinite(self.quit_time) else 0.0
        return max(default_s, min(asked, QUIT_TIME_MAX_S))

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def internal(self) -> bool:
        return self.spec.locale == ProcessLocale.INTERNAL


class _Deaf:
    """A module told to Quit at the MCP's end before anyone read its command channel: its quit
    grace, and when its process last made progress (runnable or using CPU)."""

    __slots__ = ('grace', 'progress_at', 'cpu_s')

    def __init__(self, grace: float, now: float) -> None:
        self.grace, self.progress_at, self.cpu_s = grace, now, -1.0

    def stalled(self, pid: int, now: float) -> bool:
        """Whether the process has made no progress for :data:`DEAF_WAIT_S`."""
        state = process_state(pid)
        if state is None:
            return False
        if state.runnable or state.cpu_s > self.cpu_s:
            self.progress_at, self.cpu_s = now, state.cpu_s
        return now - self.progress_at >= DEAF_WAIT_S


class Supervisor:
    """Supervises the modules of one MCP configuration."""

    def __init__(self, manager: CommsManager, config: McpConfig, *, log_directory: str,
                 bin_directory: str = '', max_restarts: int = MAX_RESTARTS) -> None:
        """Watch every module of ``config`` and supply the MCP's request and control streams.

        :param manager: the MCP's manager; its name is this MCP's name.
        :param config: the modules and mappings (read and validated).
        :param log_directory: where each started module's output log goes; also holds its
            ``NAME.resume`` state file.
        :param bin_directory: a directory searched for the modules' binaries before the ament
            index and ``PATH`` ('': none).
        :param max_restarts: restarts of one module within :data:`RESTART_WINDOW_S` before the MCP
            gives up on it.
        """
        self.manager = manager
        self.config = config
        self.log_directory = log_directory
        self.bin_directory = bin_directory
        self.max_restarts = max_restarts
        self.modules: dict[str, Module] = {}
        self.idled_for: str | None = None
        #: This MCP's name (its CommsManager's): its streams, and what its modules are told.
        self.name = manager.name
        #: External modules whose commands were withheld because another MCP owns them (told once).
        self._not_ours: set[str] = set()
        self._table_at = 0.0
        self._changed = True
        # The MCP's channels are MCP traffic: they flow while the MCP itself idles or quits
        # (its last act is to command everyone to Quit).
        self.mcp = robot_object_class('McpRequest')(mcp_stream(self.name))
        self.mcp.set_queue_mode(True)
        self.mcp.set_mcp_traffic(True)
        manager.register_supplier(self.mcp)
        self.control = robot_object_class('SimpleControl')(control_stream(self.name))
        self.control.set_queue_mode(True)
        self.control.set_mcp_traffic(True)
        manager.register_supplier(self.control)
        #: Watched time (TTLs are judged on it) and zombies declared so far.
        self.clock = SupervisionClock()
        self.zombies = 0
        #: Times a module was silent past its TTL by the wall clock (zombies under the old rule).
        self.wall_late = 0
        for spec in config.modules.values():
            self._watch(spec)
        #: The config's containers (issue 39), each started when a module of it starts.
        self.containers: dict[str, Container] = {}
        #: Set by the MCP node during its registration pass (every internal module runs with -r
        #: and exits by itself); suppliers asked for meanwhile start with the others.
        self.registering = False
        self.streams = StreamDesk(self.mcp, config, self.modules, self._start_on_demand)

    def close(self) -> None:
        """Release the MCP's streams and the modules' heartbeat channels, and end the containers
        (after :meth:`quit_all`)."""
        for container in self.containers.values():
            container.close()
        for obj in [self.mcp, self.control, *(m.heartbeat for m in self.modules.values())]:
            self.manager.unregister(obj)

    # -- modules -------------------------------------------------------------------------------
    def _watch(self, spec: ModuleSpec) -> Module:
        heartbeat = robot_object_class('Heartbeat')(f'heartbeat/{spec.name}')
        heartbeat.set_queue_mode(True)
        heartbeat.set_mcp_traffic(True)
        self.manager.register_consumer(heartbeat)
        module = Module(spec=spec, heartbeat=heartbeat)
        self.modules[spec.name] = module
        return module

    def _start_on_demand(self, name: str) -> bool:
        """Start a supplier a consumer asked for (an assignment or a start request).  During the
        registration pass the answer is yes without a start: a second process of a module whose
        -r run is under way would keep the pass waiting its whole timeout for that module to
        exit."""
        if self.registering:
            return self.modules[name].internal
        return self.start(name)

    def start(self, name: str, *, argv_extra: tuple[str, ...] = ()) -> bool:
        """Start an internal module (if it is not running); False when it cannot start.

        :param name: the module's name in the configuration.
        :param argv_extra: arguments added after the configured ones (before the ROS arguments).
        :returns: whether the module runs or is started (also True while a stop is under way:
            it starts again once the stop has ended it).
        """
        module = self.modules[name]
        if not module.internal:
            g_warn(f'MCP: {name} is external; the MCP watches it but cannot start it')
            return False
        module.wanted = True
        module.restart_at = None
        process = module.process
        if process is not None and process.running():
            if process.stopping():
                module.start_on_exit = True  # started again once the stop has ended it
            return True
        if process is not None:  # ended, and the loop has not looked yet: started anew here
            g_info(f'MCP: {name} exited with code {process.exit_code}')
        module.start_on_exit = False
        entry = module.spec.container and ':' in module.spec.binary     # python.module:function
        binary = module.spec.binary if entry else find_binary(module.spec.binary, self.bin_directory)
        if binary is None:
            g_error(f'MCP: binary "{module.spec.binary}" of {name} not found (absolute path, '
                    'bin-directory, ament index lib/<pkg>/<exe>, PATH)')
            self._failed_start(module)
            return False
        argv = [binary, *module.spec.args, *argv_extra, *self._ros_arguments()]
        environment = {MANAGED_ENV: module.spec.managed.name, MCP_ENV: self.name,
                       RESTART_ENV: str(module.starts),
                       STATE_ENV: os.path.join(self.log_directory, f'{name}.resume')}
        try:
            if module.spec.container:
                module.process = self._container(module.spec.container).start_module(
                    name, module.spec.binary, argv, environment)
            else:
                module.process = ModuleProcess(name, argv, self.log_directory, environment)
        except OSError as exc:
            g_error(f'MCP: cannot start {name} ({binary}): {exc}')
            self._failed_start(module)
            return False
        module.starts += 1
        module.pid = module.process.pid
        module.status = StatusMode.STARTING
        module.described = False
        module.last_beat = module.last_beat_at = None
        self._changed = True
        g_info(f'MCP: started {name} (pid {module.pid})')
        return True

    def _container(self, name: str) -> Container:
        """The container ``name`` (made at its first module's start).

        :raises OSError: the container program is not installed.
        """
        if name not in self.containers:
            binary = find_binary(CONTAINER_BINARY, self.bin_directory)
            if binary is None:
                raise FileNotFoundError(f'the container program "{CONTAINER_BINARY}" is not installed')
            self.containers[name] = Container(name, binary, self.log_directory, {MCP_ENV: self.name},
                                              self._ros_arguments(),
                                              quantum=self.config.cooperative.get(name))
        return self.containers[name]

    def _ros_arguments(self) -> list[str]:
        """What the MCP's own node was started with, its modules get: its namespace (``-r
        __ns:=/robot1``: their streams and the MCP's meet, another robot's do not) and
        ``use_sim_time`` (one clock for the whole robot)."""
        node = self.manager.node
        arguments = []
        if node.get_namespace() != '/':
            arguments += ['-r', f'__ns:={node.get_namespace()}']
        if node.get_parameter('use_sim_time').value:
            arguments += ['-p', 'use_sim_time:=true']
        return ['--ros-args', *arguments] if arguments else []

    def _failed_start(self, module: Module) -> None:
        module.status = StatusMode.DEAD
        self._schedule_restart(module, time.monotonic())

    def stop(self, name: str) -> None:
        """Quit a module and keep it down; an internal one that does not obey is escalated to
        SIGINT, SIGTERM and SIGKILL by its owner thread (this returns at once).

        :param name: the module's name in the configuration.
        """
        module = self.modules[name]
        module.wanted = False
        module.start_on_exit = False
        module.restart_at = None
        self.command_state(name, RunState.QUIT)
        if module.process is not None and module.process.running():
            grace_s = module.quit_grace()
            g_info(f'MCP: stopping {name}: Quit, then SIGINT after {grace_s:.1f} s, SIGTERM '
                   f'and SIGKILL {STOP_STEP_S:.1f} s apart')
            module.process.stop(step_s=STOP_STEP_S, grace_s=grace_s)
        self._changed = True

    def restart(self, name: str) -> None:
        """Stop a module and start it again once it has ended (internal modules; returns at
        once — the loop starts the new process when it sees the old one gone).

        :param name: the module's name in the configuration.
        """
        module = self.modules[name]
        running = module.process is not None and module.process.running()
        self.stop(name)
        module.restarts += 1
        if running:
            module.wanted = True
            module.start_on_exit = True
        else:
            self.start(name)

    def owns(self, module: Module) -> bool:
        """Whether this MCP commands ``module``: its internal modules, and the external ones
        that belong to no other MCP.  An external module another MCP started (several MCPs in
        one domain, one per host) is only watched: its own MCP idles, stops and quits it.  Which MCP
        a module belongs to is known from its heartbeat info: until that is heard, an external
        module is commanded as the seed's single MCP commands it.

        :param module: one of this supervisor's modules.
        """
        return module.internal or module.owner in ('', self.name)

    def command_state(self, name: str, state: RunState) -> None:
        """Send a run-state command to a module (through its heartbeat channel).  Run and Idle
        are held: a module that reports another state later is told again.  A module another
        MCP owns is not commanded (see :meth:`owns`).

        :param name: the module's name in the configuration.
        :param state: the run state to command.
        """
        module = self.modules[name]
        module.commanded_state = RunState(state)
        module.commanded_at = time.monotonic()
        if not self.owns(module):
            if name not in self._not_ours:
                self._not_ours.add(name)
                g_info(f'MCP: {name} belongs to MCP "{module.owner}": it is watched, not '
                       'commanded, from here')
            return
        heartbeat = module.heartbeat
        heartbeat.requests.state.set_value(state)
        heartbeat.publish_request()

    def _reconcile(self, now: float) -> None:
        """Tell again every live module whose reported state is not the Run or Idle it was
        commanded (one that came alive after the command, or missed it), at most every
        :data:`RECOMMAND_S`."""
        for module in self.modules.values():
            wanted = module.commanded_state
            if (module.status == StatusMode.ACTIVE and wanted in (RunState.RUN, RunState.IDLE)
                    and module.run_state in (RunState.RUN, RunState.IDLE)
                    and module.run_state != wanted and now - module.commanded_at >= RECOMMAND_S):
                self.command_state(module.name, wanted)

    def start_all(self) -> None:
        """Start every internal module that has a binary."""
        for module in self.modules.values():
            if module.internal:
                self.start(module.name)

    def set_all(self, state: RunState, *, except_: str | None = None) -> None:
        """Command every module but ``except_`` into ``state``.  Idling everyone (the lifecycle
        deactivated) ends a critical module's idling of the others: nobody is to come back to
        Run when it does.

        :param state: the run state to command.
        :param except_: a module left out (None: none).
        """
        if state == RunState.IDLE and except_ is None:
            self.idled_for = None
        for name in self.modules:
            if name != except_:
                self.command_state(name, state)

    def quit_all(self, wait_s: float = 10.0) -> None:
        """Quit every module and reap the internal ones: all are escalated at once, and this
        waits (at shutdown, never in the loop) up to ``wait_s`` for them to end.  A module told to
        Quit ends within about a second (it does not wait for its goodbye's acknowledgement), so
        the MCP and its modules are gone within 3 s; the escalation keeps its normal steps, since
        on a loaded machine a clean exit can take longer than 2 s.  A module that asked for a
        longer quit time (a slamModule saving its map) gets it, and the wait grows to cover it.

        :param wait_s: how long to wait for the internal modules to end (s); the escalation's
            steps are at most a fifth of it.
        """
        step_s = min(STOP_STEP_S, wait_s / 5)
        grace_s = min(STOP_GRACE_S, wait_s / 5)
        quit_at = time.monotonic()
        longest = wait_s
        # Who could hear the Quit: the readers of each module's command channel (in the log below).
        readers = {name: module.heartbeat.peers('request') for name, module in self.modules.items()}
        deaf: dict[str, _Deaf] = {}
        for module in self.modules.values():
            module.wanted = False
            module.start_on_exit = False
            module.restart_at = None
            self.command_state(module.name, RunState.QUIT)
            if module.process is not None:
                grace = module.quit_grace(grace_s)
                if readers[module.name] or not self.owns(module):
                    module.process.stop(step_s=step_s, grace_s=grace)
                else:       # not matched yet: its grace starts when it can hear (_repeat_quit)
                    deaf[module.name] = _Deaf(grace, quit_at)
                longest = max(longest, wait_s - grace_s + grace)
        deadline = self._repeat_quit(time.monotonic() + longest, deaf, step_s, wait_s - grace_s)
        for module in self.modules.values():
            process = module.process
            if process is not None:
                code = process.wait(max(0.0, deadline - time.monotonic()))
                if code is None:
                    g_error(f'MCP: {module.name} (pid {process.pid}) did not end after SIGKILL')
                else:
                    assert process.ended is not None  # the owner sets it before the exit code
                    g_info(f'MCP: {module.name} ended {process.ended - quit_at:.2f} s after '
                           f'Quit (exit code {code}; {readers[module.name]} readers of its commands)')
                module.process = None
                module.pid = 0
                module.status = StatusMode.DEAD
        for container in self.containers.values():     # their modules have ended: now the process
            container.close(wait_s=max(1.0, deadline - time.monotonic()))
        self._changed = True

    def _repeat_quit(self, deadline: float, deaf: dict[str, _Deaf], step_s: float, escalation_s: float) -> float:
        """Tell each module still running to Quit again every :data:`QUIT_REPEAT_S` until it has
        ended (or ``deadline``; the stop escalation runs meanwhile).  A module whose command
        channel had no reader yet (``deaf``: one started a moment before, discovery not done on
        a loaded machine) heard nothing: its escalation starts with the first Quit it can hear,
        or when it stops making progress for :data:`DEAF_WAIT_S` (asleep, no CPU used), or
        :data:`START_TIMEOUT_S` after its start; the deadline then grows by ``escalation_s`` and
        its quit grace.  Fresh clones' logs showed such modules still in their loop 2 s after the
        Quit, ended by the SIGINT, their goodbye's wait then meeting the SIGKILL; and a module
        whose start took over 5 s on a loaded machine ended by a SIGINT it need not have had.

        :returns: the deadline for the modules' ends.
        """
        while True:
            running = [(m, m.process) for m in self.modules.values()
                       if m.process is not None and m.process.poll() is None]
            for name in deaf.keys() - {m.name for m, _ in running}:
                del deaf[name]          # ended meanwhile
            now = time.monotonic()
            if not running or (now >= deadline and not deaf):
                return deadline
            running[0][1].wait(min(QUIT_REPEAT_S, max(0.0, deadline - now)) if not deaf else QUIT_REPEAT_S)
            for module, process in running:
                if process.poll() is not None:
                    continue
                self.command_state(module.name, RunState.QUIT)
                waiting = deaf.get(module.name)
                if waiting is None:
                    continue
                now = time.monotonic()
                if module.heartbeat.peers('request'):
                    grace = waiting.grace
                elif waiting.stalled(process.task, now) or now - process.started >= START_TIMEOUT_S:
                    g_warn(f'MCP: {module.name} never came to hear its Quit ({now - process.started:.1f} s '
                           'after its start): its stop begins without one')
                    grace = 0.0
                else:
                    continue
                del deaf[module.name]
                process.stop(step_s=step_s, grace_s=grace)
                deadline = max(deadline, now + escalation_s + grace)

    # -- the loop ------------------------------------------------------------------------------
    def tick(self) -> None:
        """Take in heartbeats, requests and exits; restart, idle and publish as needed."""
        now = time.monotonic()
        watched = self.clock.tick(now)
        for module in self.modules.values():
            self._take_heartbeats(module, now)
            self._check_exit(module, now)
            if (module.status == StatusMode.ACTIVE and module.last_beat_at is not None
                    and now - module.last_beat_at > module.ttl + TTL_GRACE_S
                    and not module.wall_late and not self._quitting(module, now)):
                module.wall_late = True
                self.wall_late += 1
        if any(self._overdue(m, now, watched) for m in self.modules.values()):
            # Before condemning anyone, take in what arrived since the last exchange.
            self.manager.step()
            for module in self.modules.values():
                self._take_heartbeats(module, now)
        for module in self.modules.values():
            self._check_ttl(module, now, watched)
            if module.restart_at is not None and now >= module.restart_at and module.wanted:
                module.restart_at = None
                self.start(module.name)
        self._critical()
        self._reconcile(now)
        self.streams.serve()
        self._control()
        if self._changed or now - self._table_at >= TABLE_PERIOD_S:
            self._publish_table(now)

    def _take_heartbeats(self, module: Module, now: float) -> None:
        heartbeat = module.heartbeat
        described = False
        while heartbeat.get_next_info():
            info = heartbeat.info
            if info.pid.get_value() in module.dead_pids:
                continue                        # the last process's, delivered after its exit
            module.described = True
            module.run_state = RunState(info.state.get_value())
            module.pid = info.pid.get_value()
            module.host = info.host.get_value()
            module.owner = info.mcp.get_value()
            module.quit_time = info.quit_time.get_value()
            if module.trust_ttl != bool(info.trust_ttl.get_value()):
                module.trust_ttl = not module.trust_ttl
                self._judge_ttl(module)
            module.supplies = list(zip(info.interfaces.get_value(), info.streams.get_value()))
            described = True
            self._changed = True
        if described:
            self.streams.check(module)
        beats = 0
        while heartbeat.get_next_data():
            beats += 1
            module.announced_ttl = heartbeat.data.ttl
            self._judge_ttl(module)
        if beats:
            module.last_beat = self.clock.now()
            module.last_beat_at = now
            module.wall_late = False
            module.stalled_at = None
            if module.status != StatusMode.ACTIVE and module.described:
                module.status = StatusMode.ACTIVE
                module.ever_active = True
                self._changed = True
                g_info(f'MCP: {module.name} is alive')

    @staticmethod
    def _judge_ttl(module: Module) -> None:
        """Take the module's announced TTL within :data:`TTL_RANGE_S` (up to
        :data:`TRUSTED_TTL_MAX_S` when it asks to be trusted); again whenever either changes."""
        ttl = module.announced_ttl
        low, high = TTL_RANGE_S[0], TRUSTED_TTL_MAX_S if module.trust_ttl else TTL_RANGE_S[1]
        if not math.isfinite(ttl) or not low <= ttl <= high:
            clamped = min(max(ttl if math.isfinite(ttl) else high, low), high)
            if module.ttl != clamped:
                g_warn(f'MCP: {module.name} announces TTL {ttl!r} s; using {clamped} s'
                       + ('' if module.trust_ttl or ttl < low else
                          ' (set_heartbeat_only(ttl, trust=True) asks the MCP to trust it)'))
            ttl = clamped
        module.ttl = ttl

    def _check_exit(self, module: Module, now: float) -> None:
        process = module.process
        if process is not None and not process.running():
            self._ended(module, process, now)

    def _ended(self, module: Module, process: ModuleProcess | ContainedProcess, now: float) -> None:
        """The owner has reaped ``process``: record it, restart when wanted."""
        code = process.exit_code
        module.dead_pids.add(process.pid)
        module.process = None
        module.pid = 0
        module.status = StatusMode.DEAD
        # Beats carry no pid: the dead process's last ones, arriving late on a loaded machine,
        # must not make it alive again (test_no_stall saw a stopped module back as ACTIVE with
        # pid 0, then a zombie); only a new process that describes itself does.
        module.described = False
        self._changed = True
        late = f'{1000 * (now - process.ended):.0f} ms after the exit' if process.ended else ''
        text = f'MCP: {module.name} exited with code {code} (noticed at monotonic {now:.3f}, {late})'
        if module.start_on_exit:
            g_info(text)
            module.start_on_exit = False
            self.start(module.name)
        elif module.wanted and module.spec.managed != ProcessType.UNMANAGED:
            g_warn(text)
            self._schedule_restart(module, now)
        else:
            g_info(text)

    def _overdue(self, module: Module, now: float, watched: float) -> bool:
        """Silent past the TTL, judged against the MCP's own lag (see :mod:`wurde_mcp.clock`)."""
        if module.status != StatusMode.ACTIVE or module.last_beat_at is None \
                or module.last_beat is None or self._quitting(module, now):
            return False
        limit = module.ttl + TTL_GRACE_S
        if now - module.last_beat_at <= limit:
            return False
        return watched - module.last_beat > limit or self.clock.steady_for(now) >= REVIEW_S

    @staticmethod
    def _quitting(module: Module, now: float) -> bool:
        """Whether the module was told to Quit and is still within its time to end: a module
        saving what it holds sends no beats, and its stop escalation (its quit grace, then the
        signals) bounds it, not its TTL."""
        if module.process is not None:
            return module.process.stopping()
        return (module.commanded_state == RunState.QUIT
                and now - module.commanded_at <= module.quit_grace() + module.ttl)

    def _check_ttl(self, module: Module, now: float, watched: float) -> None:
        if module.status == StatusMode.STARTING and module.process is not None:
            if now - module.process.started <= START_TIMEOUT_S:
                return
            threads = where_threads_wait(module.process.task)
            g_warn(f'MCP: {module.name} sent no heartbeat within {START_TIMEOUT_S:.0f} s of its '
                   'start: zombie' + (f'; its threads (name, state, kernel wait): {threads}' if threads else ''))
        elif not self._overdue(module, now, watched) or self._working(module, now):
            return
        else:
            assert module.last_beat is not None and module.last_beat_at is not None
            threads = where_threads_wait(module.process.task) if module.process is not None else ''
            g_warn(f'MCP: {module.name} missed its TTL ({module.ttl:.3f} s): zombie (noticed at '
                   f'monotonic {now:.3f}; silent {watched - module.last_beat:.3f} s watched, '
                   f'{now - module.last_beat_at:.3f} s by the clock)'
                   + (f'; its threads (name, state, kernel wait): {threads}' if threads else ''))
        module.status = StatusMode.ZOMBIE
        self.zombies += 1
        self._changed = True
        if (module.internal and module.wanted and module.process is not None
                and module.spec.managed != ProcessType.UNMANAGED):
            module.process.signal(9)  # a hung module gets no second chance to hang on exit

    def _working(self, module: Module, now: float) -> bool:
        """Whether a module silent past its TTL is still working (:mod:`wurde_mcp.progress`):
        not stopped, silent less than :data:`HARD_TTLS` TTLs, and runnable or using CPU within
        the last :data:`NO_PROGRESS_S`.  Only the MCP's own children are looked at."""
        if module.process is None or not module.internal or module.last_beat_at is None:
            return False
        state = process_state(module.process.task)
        if state is None or state.stopped or now - module.last_beat_at > HARD_TTLS * module.ttl:
            return False
        if module.stalled_at is None or state.runnable or state.cpu_s > module.stalled_cpu:
            if module.stalled_at is None:
                g_info(f'MCP: {module.name} is silent past its TTL but its process is working '
                       f'(starved of CPU?): a zombie only if it stays silent {HARD_TTLS:g} TTLs '
                       f'or stops making progress for {NO_PROGRESS_S:g} s')
            module.stalled_at, module.stalled_cpu = now, state.cpu_s
            return True
        return now - module.stalled_at < NO_PROGRESS_S

    def _schedule_restart(self, module: Module, now: float) -> None:
        if module.spec.managed == ProcessType.UNMANAGED or not module.wanted:
            return
        recent = [t for t in module.recent_restarts if now - t < RESTART_WINDOW_S]
        if len(recent) >= self.max_restarts:
            module.status = StatusMode.FAILED
            module.wanted = False
            self._changed = True
            g_error(f'MCP: giving up on {module.name} after {len(recent)} restarts within '
                    f'{RESTART_WINDOW_S:.0f} s')
            return
        delay = BACKOFF_S[min(len(recent), len(BACKOFF_S) - 1)]
        module.recent_restarts = [*recent, now]
        module.restarts += 1
        module.restart_at = now + delay

    def _critical(self) -> None:
        """While a critical module that has run is not up in Run (and was not told to idle),
        every other module is Idle.  One that is alive and was told to Run only a moment ago is
        given :data:`RECOMMAND_S` to say so: the command may still be on its way (without this,
        every activation flipped all modules Run → Idle → Run)."""
        now = time.monotonic()
        down = next((m.name for m in self.modules.values()
                     if m.spec.managed == ProcessType.CRITICAL and m.ever_active
                     and m.commanded_state == RunState.RUN
                     and (m.status != StatusMode.ACTIVE
                          or (m.run_state != RunState.RUN
                              and now - m.commanded_at >= RECOMMAND_S))), None)
        if down is not None and self.idled_for is None:
            self.idled_for = down
            g_warn(f'MCP: critical module {down} is down: every other module goes Idle')
            self.set_all(RunState.IDLE, except_=down)
        elif down is None and self.idled_for is not None:
            g_info(f'MCP: critical module {self.idled_for} is back: every module goes to Run')
            self.idled_for = None
            self.set_all(RunState.RUN)

    def summary(self) -> str:
        """One line on how supervision went: zombies, wall-clock lateness, the MCP's stalls."""
        clock = self.clock
        return (f'MCP: supervision summary: {self.zombies} zombies; {self.wall_late} times a '
                f'module was silent past its TTL by the wall clock; {clock.stalls} MCP stalls '
                f'past {1000 * clock.max_gap_s:.0f} ms, {clock.discounted_s:.3f} s discounted, '
                f'longest gap {1000 * clock.longest_gap_s:.0f} ms')

    # -- control and the module table ----------------------------------------------------------
    def _control(self) -> None:
        while self.control.get_next_request():
            request = self.control.requests
            command = request.command.get_value()
            name = request.module.get_value()
            if command == CMD_QUIT_ALL:
                for module in list(self.modules):
                    self.stop(module)
            elif name not in self.modules:
                g_warn(f'MCP: control command {command} for unknown module "{name}"')
            elif not self.owns(self.modules[name]):
                owner = self.modules[name].owner
                g_warn(f'MCP: control command {command} for {name} not carried out: it belongs '
                       f'to MCP "{owner}" (mcp_controller --mcp {owner} reaches it)')
            elif command == CMD_START:
                self.modules[name].restarts = 0
                self.modules[name].recent_restarts = []
                self.start(name)
            elif command == CMD_STOP:
                self.stop(name)
            elif command == CMD_RESTART:
                self.restart(name)
            elif command == CMD_STATE:
                self.command_state(name, RunState(request.state.get_value()))
            self._changed = True

    def _publish_table(self, now: float) -> None:
        modules = list(self.modules.values())
        data = self.control.data
        data.module_names = [m.name for m in modules]
        data.module_status = [m.status for m in modules]
        data.module_managed = [m.spec.managed for m in modules]
        data.module_locale = [m.spec.locale for m in modules]
        data.module_state = [m.run_state for m in modules]
        data.module_pid = [m.pid for m in modules]
        data.module_host = [m.host for m in modules]
        data.module_heartbeat_age = [now - m.last_beat_at if m.last_beat_at is not None
                                     else -1.0 for m in modules]
        data.module_restarts = [m.restarts for m in modules]
        self.control.publish_data()
        self._table_at = now
        self._changed = False
