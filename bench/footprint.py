"""Benchmark: what the whole simulated Pluto costs its computer, beside raw rclpy (issue 39).

config/pluto as shipped (the MCP and the twelve modules it starts: the five dummies, localModule,
poseModule, driveModule, avoidModule, motionModule, map_server, navigator) runs under one MCP with
``-a`` while the ``mission`` client drives the same route in every run: the office map's places
:data:`ROUTE` in order, from the start place (the simulator's seed fixed by sim-config.xml).  Then:

1. **The robot's traffic.**  After ``--warmup`` seconds of driving, a survey node reads the ROS
   graph (each module's publishers and subscriptions, with their types and QoS) and counts, for
   ``--rate-seconds``, the messages on every topic a module publishes, by publisher: a topic with
   one publisher is that module's; on a topic several publish (a WURDE request channel, ``/rosout``,
   ``/parameter_events``, ``/tf_static``) each message is told by its WURDE session (learnt from
   the topics each module publishes alone, such as its heartbeat), its logger or its node.  The
   standard mirrors that the dummies send only while someone watches (``bench/mirrors_cpu.py``'s
   topics) are not subscribed: they are unwatched in the robot and stay silent.  The survey ends
   before the measurement, so that it adds nothing to it.
2. **The robot.**  For ``--seconds`` of driving, each process's CPU (user + system time from
   /proc/PID/stat, as % of one core) and PSS (the ``Pss:`` line of /proc/PID/smaps_rollup, sampled
   every 10 s and averaged, MB); processes are named by their module (``-n NAME`` of the command
   line the MCP ran).  The mission client is measured too, outside the robot's total.
3. **The raw rclpy baseline, twice.**  With the robot ended, one process per module (and one for
   the mission client) runs ``bench/footprint_baseline.py``: a plain rclpy node named after the
   module with its publishers and subscriptions (same topics, types and QoS), publishing at the
   rates counted in 1 a message taken from the robot, doing no work.  A module's topics of about
   the same rate (within :data:`SAME_RATE` of each other) share one timer, as one loop publishing
   them would.  First with rclpy's default executor, then with
   ``rclpy.experimental.EventsExecutor``; each measured as in 2.

The table has, per process, CPU % and PSS MB of the robot, of the baseline and of the baseline on
the EventsExecutor, and their totals.  Every process started is ended (SIGINT, then SIGKILL), and
none may be left carrying the run's log directory.  DDS on loopback only, in a ROS domain of its
own.

``--containers 'NAME=module,module NAME=...'`` (or ``all``: one container ``robot`` of all twelve)
runs those modules in ``<container>``s of the MCP config (:mod:`wurde_mcp.container`): the robot's
rows are then its processes — the MCP, each container, each module left on its own — and the
baseline stays one process per module; a contained module's own row gives its thread's CPU (its
PSS is the container's), which the total does not count again.  ``--scheduling cooperative``
makes those containers cooperative (:mod:`wurde_core.cooperative`): their modules are tasks of one
thread, so their own rows stay empty.

Usage: ``make bench-footprint`` or ``python bench/footprint.py [--seconds 60] [--rate-seconds 20]
[--containers all] [--scheduling cooperative] [--robot-only]``; ``--robot-only`` leaves the baselines out (their cells
empty), to compare two versions of the robot quickly.
"""

from __future__ import annotations

import argparse
import base64
import functools
import json
import math
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

from mirrors_cpu import cpu_seconds
from mirrors_cpu import topics as mirror_topics
from soak import interrupt, orphans, require_loopback, start_mcp, start_mission

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
PLUTO = ROOT / 'config' / 'pluto'
BASELINE = HERE / 'footprint_baseline.py'
#: The mission's route: places of config/pluto's office map, by name, in order.
ROUTE = ('office2', 'lab', 'kitchen', 'corridor_east', 'conference', 'start')
#: The MCP's node (its process is the one started here).
MCP = 'MCP'
#: The client that drives the route: measured, outside the robot's total.
CLIENT = 'mission'
#: Topics every rclpy node publishes on its own (its logger, its parameter events): the baseline
#: makes them again only when the module sent something on them while counted.
BUILT_IN = ('/rosout', '/parameter_events')
#: Publishers of one module whose rates are within this share of each other share a timer.
SAME_RATE = 0.05
#: Seconds between PSS samples.
PSS_EVERY_S = 10.0
#: The machine's 1-minute load average as each window began (the machine may be shared).
LOADS: dict[str, float] = {}


def pss_mb(pid: int) -> float:
    """Proportional set size of ``pid`` (MB), from /proc/PID/smaps_rollup."""
    for line in pathlib.Path(f'/proc/{pid}/smaps_rollup').read_text().splitlines():
        if line.startswith('Pss:'):
            return int(line.split()[1]) / 1024
    return math.nan


def children(pid: int) -> list[int]:
    """Live child processes of ``pid``."""
    found = []
    for entry in pathlib.Path('/proc').iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / 'stat').read_text().rsplit(')', 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid and fields[0] != 'Z':
            found.append(int(entry.name))
    return found


def module_name(pid: int) -> str:
    """The module a process runs: its ``-n NAME``, else its program's name."""
    try:
        argv = pathlib.Path(f'/proc/{pid}/cmdline').read_bytes().decode(errors='replace').split('\0')
    except OSError:
        return f'pid {pid}'
    if '-n' in argv[:-1]:
        return argv[argv.index('-n') + 1]
    return pathlib.Path(argv[1] if len(argv) > 1 else argv[0]).name


@dataclass
class Usage:
    """One process over the window."""

    cpu: float = math.nan                  # % of one core
    pss: float = math.nan                  # MB, mean of the samples
    ended: bool = False                    # the process ended within the window


def thread_seconds(pid: int) -> dict[str, float]:
    """CPU seconds of ``pid``'s threads by their kernel name (a container names each module's
    thread after it, :func:`wurde_mcp.container.host.name_os_thread`)."""
    found: dict[str, float] = defaultdict(float)
    for task in pathlib.Path(f'/proc/{pid}/task').iterdir():
        try:
            found[(task / 'comm').read_text().strip()] += cpu_seconds(pid, int(task.name))
        except OSError:
            continue
    return found


def measure(pids: dict[str, int], seconds: float,
            contained: dict[str, list[str]] | None = None) -> dict[str, Usage]:
    """CPU and PSS of each process over ``seconds`` of wall time (this process sleeps meanwhile);
    with ``contained`` (container name: its modules), each contained module's CPU too, from its
    thread (its PSS is the container's: nan)."""
    start: dict[str, float] = {}
    for name, pid in pids.items():
        start[name] = cpu_seconds(pid)
    contained = {c: members for c, members in (contained or {}).items() if c in pids}
    threads_before = {c: thread_seconds(pids[c]) for c in contained}
    samples: dict[str, list[float]] = defaultdict(list)
    ended: set[str] = set()
    began = time.monotonic()
    next_sample = began
    while True:
        now = time.monotonic()
        if now >= next_sample or now - began >= seconds:
            for name, pid in pids.items():
                try:
                    samples[name].append(pss_mb(pid))
                except OSError:
                    ended.add(name)
            next_sample += PSS_EVERY_S
        if now - began >= seconds:
            break
        time.sleep(min(0.5, max(0.0, began + seconds - now), max(0.0, next_sample - now)))
    elapsed = time.monotonic() - began
    usage = {}
    for name, pid in pids.items():
        try:
            cpu = 100 * (cpu_seconds(pid) - start[name]) / elapsed
        except OSError:
            cpu = math.nan
            ended.add(name)
        pss = sum(samples[name]) / len(samples[name]) if samples[name] else math.nan
        usage[name] = Usage(cpu, pss, name in ended)
    for container, members in contained.items():
        try:
            after = thread_seconds(pids[container])
        except OSError:
            continue
        for member in members:
            comm = member.encode()[:15].decode(errors='ignore')
            if comm in after:
                used = after[comm] - threads_before[container].get(comm, 0.0)
                usage[member] = Usage(100 * used / elapsed, math.nan, False)
    return usage


# -- the robot's traffic -------------------------------------------------------------------------

@dataclass
class Endpoint:
    """One publisher or subscription of a module."""

    topic: str
    type: str
    qos: dict[str, Any]
    rate: float = 0.0                      # messages per second (publishers)
    sample: bytes | None = None            # one serialized message it sent (publishers)


@dataclass
class Traffic:
    """Each module's endpoints as the survey found them."""

    publishers: dict[str, list[Endpoint]] = field(default_factory=dict)
    subscriptions: dict[str, list[Endpoint]] = field(default_factory=dict)
    unattributed: int = 0                  # messages on a shared topic whose publisher was not told


def containers_of(text: str, modules: list[str]) -> dict[str, list[str]]:
    """``--containers``' groups: ``all`` is one container ``robot`` of every module."""
    if text.strip() == 'all':
        return {'robot': list(modules)}
    groups = {}
    for group in text.split():
        name, _, members = group.partition('=')
        groups[name] = [m for m in members.split(',') if m]
        unknown = sorted(set(groups[name]) - set(modules))
        if unknown:
            raise SystemExit(f'footprint: --containers names modules config/pluto has not: {unknown}')
    return groups


def contain(config: pathlib.Path, groups: dict[str, list[str]], scheduling: str = 'threads') -> None:
    """Rewrite the MCP config at ``config`` with ``groups``' modules in ``<container>``s of that
    ``scheduling``."""
    from lxml import etree
    tree = etree.parse(str(config))
    root = tree.getroot()
    for name, members in groups.items():
        container = etree.SubElement(root, 'container', name=name, scheduling=scheduling)
        for module in root.findall('module'):
            if module.get('name') in members:
                container.append(module)
    tree.write(str(config), xml_declaration=True, encoding='UTF-8')


def qos_spec(profile: Any) -> dict[str, Any]:
    """Reliability, durability and depth of a profile seen on the graph.  Discovery does not carry
    the history depth: an unknown depth is taken as 1 (WURDE's latest mode; its queue mode keeps
    1000)."""
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
    depth = profile.depth if profile.depth and profile.depth > 0 else 1
    return {'reliability': 'reliable' if profile.reliability == ReliabilityPolicy.RELIABLE else 'best_effort',
            'durability': ('transient_local' if profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                           else 'volatile'),
            'depth': depth}


def publisher_key(topic: str, message: Any) -> tuple[str, Any] | None:
    """What tells who sent ``message`` on a topic several publish: the node of a parameter event,
    the logger of a log line, the WURDE session of anything else (None: nothing tells)."""
    if topic == '/parameter_events':
        return 'node', message.node.lstrip('/')
    if topic == '/rosout':
        return 'node', message.name.split('.')[0]
    header = getattr(message, 'header', None)
    session = getattr(header, 'session', None)
    if session is not None:
        return 'session', int(session)
    return None


def own(endpoints: list[Any], name: str) -> list[Any]:
    """The endpoints of node ``name`` among ``endpoints`` ([None] when the graph lists none: one
    of default QoS is made)."""
    return [e for e in endpoints if e.node_name == name] or [None]


def survey(domain_id: int, names: list[str], seconds: float, settle: float) -> Traffic:
    """Every endpoint of the modules ``names`` and what each publisher sends per second, counted
    for ``seconds`` after ``settle`` (see the module's docstring, step 1)."""
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    from rclpy.serialization import deserialize_message

    from footprint_baseline import message_type

    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    node = rclpy.create_node('footprint_survey', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    traffic = Traffic()
    try:
        deadline = time.monotonic() + 60
        while not set(names) <= set(node.get_node_names()):
            if time.monotonic() > deadline:
                raise SystemExit(f'footprint: nodes missing from the graph: '
                                 f'{sorted(set(names) - set(node.get_node_names()))}')
            executor.spin_once(timeout_sec=0.2)
        time.sleep(2.0)                                    # their endpoints discovered too
        published = {name: node.get_publisher_names_and_types_by_node(name, '/') for name in names}
        subscribed = {name: node.get_subscriber_names_and_types_by_node(name, '/') for name in names}
        kinds = {topic: types[0] for entries in (*published.values(), *subscribed.values())
                 for topic, types in entries}
        writers = {topic: node.get_publishers_info_by_topic(topic) for topic in kinds}
        readers = {topic: node.get_subscriptions_info_by_topic(topic) for topic in kinds}
        unwatched = set(mirror_topics())
        counted = {topic for entries in published.values() for topic, _ in entries} - unwatched
        by_writer: dict[str, dict[str, int]] = defaultdict(lambda: defaultdict(int))
        by_key: dict[str, dict[tuple[str, Any] | None, int]] = defaultdict(lambda: defaultdict(int))
        samples: dict[tuple[str, Any], bytes] = {}
        seen: dict[str, set[tuple[str, Any] | None]] = defaultdict(set)
        sessions: dict[int, str] = {}
        state = {'counting': False}

        def take(topic: str, raw: bytes, _info: Any) -> None:
            sole = [w.node_name for w in writers[topic]]
            if len(sole) == 1:
                samples[(topic, sole[0])] = raw
                if sole[0] not in sessions.values() and topic.startswith('/wurde/'):
                    key = publisher_key(topic, deserialize_message(raw, message_type(kinds[topic])))
                    if key is not None and key[0] == 'session':
                        sessions[key[1]] = sole[0]
                if state['counting']:
                    by_writer[topic][sole[0]] += 1
                return
            key = publisher_key(topic, deserialize_message(raw, message_type(kinds[topic])))
            samples[(topic, key)] = raw
            seen[topic].add(key)
            if state['counting']:
                by_key[topic][key] += 1

        for topic in sorted(counted):
            offers = [w.qos_profile for w in writers[topic]]
            profile = QoSProfile(
                history=HistoryPolicy.KEEP_LAST, depth=1000,
                reliability=(ReliabilityPolicy.RELIABLE if all(o.reliability == ReliabilityPolicy.RELIABLE
                                                               for o in offers) else ReliabilityPolicy.BEST_EFFORT),
                durability=(DurabilityPolicy.TRANSIENT_LOCAL
                            if offers and all(o.durability == DurabilityPolicy.TRANSIENT_LOCAL for o in offers)
                            else DurabilityPolicy.VOLATILE))
            node.create_subscription(message_type(kinds[topic]), topic, functools.partial(take, topic), profile,
                                     raw=True)

        def spin(length: float) -> None:
            until = time.monotonic() + length
            while time.monotonic() < until:
                executor.spin_once(timeout_sec=0.05)

        spin(settle)
        state['counting'] = True
        began = time.monotonic()
        spin(seconds)
        elapsed = time.monotonic() - began
        state['counting'] = False

        def who(topic: str, key: tuple[str, Any] | None) -> str | None:
            if key is None:
                return None
            name = sessions.get(key[1]) if key[0] == 'session' else key[1]
            return name if name in {w.node_name for w in writers[topic]} else None

        for topic, keys in by_key.items():
            for key, count in keys.items():
                name = who(topic, key)
                if name is None:
                    traffic.unattributed += count
                else:
                    by_writer[topic][name] += count
        for topic, found in seen.items():
            for key in found:
                name = who(topic, key)
                if name is not None:
                    samples[(topic, name)] = samples[(topic, key)]
            # A publisher not told apart (a /tf_static sent before the survey) gets another's message.
            for writer in writers[topic]:
                samples.setdefault((topic, writer.node_name), samples[(topic, next(iter(found)))])
        for name in names:
            entries = []
            for topic, types in published[name]:
                mine = own(writers[topic], name)
                for writer in mine:
                    qos = qos_spec(writer.qos_profile) if writer is not None else qos_spec(QoSProfile(depth=1))
                    entries.append(Endpoint(topic, types[0], qos, by_writer[topic][name] / elapsed / len(mine),
                                            samples.get((topic, name))))
            traffic.publishers[name] = entries
            traffic.subscriptions[name] = [
                Endpoint(topic, types[0], qos_spec(reader.qos_profile) if reader is not None
                         else qos_spec(QoSProfile(depth=1)))
                for topic, types in subscribed[name]
                for reader in own(readers[topic], name)]
    finally:
        executor.shutdown()
        node.destroy_node()
        context.try_shutdown()
    return traffic


def timers(endpoints: list[Endpoint]) -> list[tuple[float, list[int]]]:
    """The publishers of one module with traffic, grouped by rate: publishers within
    :data:`SAME_RATE` of the slowest of a group share a timer at the group's mean rate."""
    timed = sorted((e.rate, i) for i, e in enumerate(endpoints) if e.rate > 0)
    groups: list[list[tuple[float, int]]] = []
    for rate, index in timed:
        if groups and rate <= groups[-1][0][0] * (1 + SAME_RATE):
            groups[-1].append((rate, index))
        else:
            groups.append([(rate, index)])
    return [(sum(r for r, _ in group) / len(group), [i for _, i in group]) for group in groups]


def baseline_spec(traffic: Traffic) -> dict[str, Any]:
    """The JSON spec of ``bench/footprint_baseline.py`` for every module surveyed."""
    spec = {}
    for name, endpoints in traffic.publishers.items():
        kept = [e for e in endpoints if e.topic not in BUILT_IN or e.rate > 0]
        spec[name] = {
            'publishers': [{'topic': e.topic, 'type': e.type, 'qos': e.qos, 'rate': e.rate,
                            'sample': base64.b64encode(e.sample).decode() if e.sample is not None else None}
                           for e in kept],
            'subscriptions': [{'topic': e.topic, 'type': e.type, 'qos': e.qos}
                              for e in traffic.subscriptions[name]],
            'timers': timers(kept)}
    return spec


# -- the runs ------------------------------------------------------------------------------------

def run_robot(args: argparse.Namespace, domain_id: int, work: pathlib.Path, env: dict[str, str],
              groups: dict[str, list[str]]) -> tuple[dict[str, Usage], Traffic, list[str]]:
    """config/pluto driving the route: its traffic surveyed, then its processes measured."""
    from wurde_core import CommsManager, RunState, StatusMode
    from wurde_core.interfaces import SimpleControl
    from wurde_core.mcp_client import control_stream

    notes: list[str] = []
    rows: dict[str, tuple[StatusMode, RunState, int]] = {}
    mcp = start_mcp(work, env)
    mission: subprocess.Popen[bytes] | None = None
    modules: dict[str, int] = {}

    try:
        manager = CommsManager(f'Footprint{os.getpid()}')
        manager.set_no_sleep()
        manager.set_no_heartbeat()
        table = SimpleControl(control_stream())
        table.set_queue_mode(True)
        manager.register_consumer(table)
        try:
            deadline = time.monotonic() + 180
            while not (len(rows) > 1 and all(s == StatusMode.ACTIVE and r == RunState.RUN
                                             for s, r, _ in rows.values())):
                if time.monotonic() > deadline:
                    raise SystemExit(f'footprint: the robot not up in Run within 180 s; table {rows}')
                manager.step()
                while table.get_next_data():
                    d = table.data
                    rows.update({n: (StatusMode(s), RunState(r), p) for n, s, r, p in zip(
                        d.module_names, d.module_status, d.module_state, d.module_pid)})
                manager.wait(0.05)
        finally:
            manager.clean_up()
        print(f'footprint: {len(rows)} modules up in Run; driving {" -> ".join(ROUTE)}', flush=True)
        mission = start_mission(work, env, ROUTE)
        time.sleep(args.warmup)
        traffic = survey(domain_id, list(dict.fromkeys([MCP, *rows, CLIENT])), args.rate_seconds, settle=3.0)
        time.sleep(5.0)                                    # the survey's node gone from the graph
        modules = {MCP: mcp.pid, **{module_name(pid): pid for pid in children(mcp.pid)}}
        contained = {member for members in groups.values() for member in members}
        missing = sorted((set(rows) - contained | set(groups)) - set(modules))
        if missing:
            raise SystemExit(f'footprint: no process for {", ".join(missing)}')
        if mission.poll() is not None:
            notes.append('the mission had ended before the window; started again')
            mission = start_mission(work, env, ROUTE)
        LOADS['robot'] = os.getloadavg()[0]
        print(f'footprint: the robot for {args.seconds:.0f} s (load average {LOADS["robot"]:.2f})', flush=True)
        usage = measure({**modules, CLIENT: mission.pid}, args.seconds, groups)
        if mission.poll() is not None:
            notes.append('the mission ended within the window')
        after = {MCP: mcp.pid, **{module_name(pid): pid for pid in children(mcp.pid)}}
        for name, pid in modules.items():
            if after.get(name) != pid:
                notes.append(f'{name} restarted or ended within the window (pid {pid} -> {after.get(name)})')
    finally:
        if mission is not None:
            interrupt(mission, 30.0)
        interrupt(mcp, 60.0)
        for pid in modules.values():
            try:
                os.kill(pid, signal.SIGKILL)
                notes.append(f'pid {pid} left after the MCP ended: killed')
            except ProcessLookupError:
                pass
    goals = [line for line in (work / 'mission.out').read_text(errors='replace').splitlines()
             if line.startswith('mission: ') and ' after ' in line]
    notes.extend(goals)
    return usage, traffic, notes


def run_baseline(executor: str, spec_file: pathlib.Path, names: list[str], seconds: float, settle: float,
                 work: pathlib.Path, env: dict[str, str]) -> tuple[dict[str, Usage], list[str]]:
    """One process per module running ``bench/footprint_baseline.py`` with ``executor``, measured."""
    notes: list[str] = []
    processes: dict[str, subprocess.Popen[bytes]] = {}
    outputs = {name: work / f'baseline-{executor}-{name}.out' for name in names}
    try:
        for name in names:
            with open(outputs[name], 'wb') as out:
                processes[name] = subprocess.Popen(
                    [sys.executable, str(BASELINE), '--spec', str(spec_file), '--node', name, '--executor', executor],
                    env=env, stdout=out, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 120
        waiting = set(names)
        while waiting:
            for name in sorted(waiting):
                if 'baseline ready' in outputs[name].read_text(errors='replace'):
                    waiting.discard(name)
                elif processes[name].poll() is not None:
                    raise SystemExit(f'footprint: the baseline of {name} ended:\n{outputs[name].read_text()}')
            if time.monotonic() > deadline:
                raise SystemExit(f'footprint: baselines not ready within 120 s: {sorted(waiting)}')
            time.sleep(0.2)
        time.sleep(settle)                                 # discovery and the first deliveries
        LOADS[executor] = os.getloadavg()[0]
        print(f'footprint: the raw rclpy baseline ({executor} executor) for {seconds:.0f} s '
              f'(load average {LOADS[executor]:.2f})', flush=True)
        usage = measure({name: p.pid for name, p in processes.items()}, seconds)
    finally:
        for name, process in processes.items():
            interrupt(process, 20.0)
            if process.returncode not in (0, None, -signal.SIGINT):
                notes.append(f'the {executor} baseline of {name} ended with {process.returncode}')
    return usage, notes


def cell(usage: Usage | None) -> str:
    if usage is None:
        return ' | '
    flag = ' (ended)' if usage.ended else ''
    pss = '-' if math.isnan(usage.pss) else f'{usage.pss:.0f}'
    return f'{usage.cpu:.1f}{flag} | {pss}'


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=60.0, help='the measured window of each run (s)')
    parser.add_argument('--rate-seconds', type=float, default=20.0, help="the survey of the robot's traffic (s)")
    parser.add_argument('--warmup', type=float, default=10.0, help='driving before the survey (s)')
    parser.add_argument('--settle', type=float, default=10.0, help='the baseline up before its window (s)')
    parser.add_argument('--containers', default='', help="'NAME=module,module ...', or all: modules in <container>s")
    parser.add_argument('--scheduling', choices=('threads', 'cooperative'), default='threads',
                        help="the containers' scheduling (wurde_core.cooperative)")
    parser.add_argument('--robot-only', action='store_true',
                        help='measure the robot only, not the raw rclpy baselines (to compare two versions of it)')
    args = parser.parse_args()
    require_loopback('footprint', 'make bench-footprint')
    from wurde_testing import claim_domain_id

    command = ' '.join(['python', *sys.argv])
    started = time.strftime('%Y-%m-%d %H:%M')
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    work = pathlib.Path(tempfile.mkdtemp(prefix='wurde-footprint-'))
    for path in PLUTO.iterdir():
        shutil.copy(path, work / path.name)                # map.xml: the file it links to
    from wurde_mcp.config import read_mcp_config
    groups = containers_of(args.containers, list(read_mcp_config(PLUTO / 'mcp-config.xml').modules)) \
        if args.containers else {}
    contain(work / 'mcp-config.xml', groups, args.scheduling)
    marker = f'WURDE_LOG_DIRECTORY={work}'
    env = dict(os.environ, WURDE_CONFIG_DIR=str(work), WURDE_LOG_DIRECTORY=str(work), WURDE_DATA_DIR=str(work))
    print(f'footprint: {started}, {os.cpu_count()} cores, ROS_DOMAIN_ID={claim.domain_id}; files in {work}',
          flush=True)
    try:
        robot, traffic, notes = run_robot(args, claim.domain_id, work, env, groups)
        spec = baseline_spec(traffic)
        spec_file = work / 'baseline-spec.json'
        spec_file.write_text(json.dumps(spec, indent=1))
        names = list(spec)
        plain: dict[str, Usage] = {}
        events: dict[str, Usage] = {}
        if not args.robot_only:
            plain, more = run_baseline('default', spec_file, names, args.seconds, args.settle, work, env)
            notes += more
            events, more = run_baseline('events', spec_file, names, args.seconds, args.settle, work, env)
            notes += more
    finally:
        left = [pid for pid, _ in orphans(marker)]
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        claim.release()

    print(f'\nfootprint: {started}, {os.cpu_count()} cores, `{command}`; config/pluto driving '
          f'{" -> ".join(ROUTE)} (mission -P); each window {args.seconds:.0f} s, traffic counted for '
          f'{args.rate_seconds:.0f} s before it')
    print('\nThe robot\'s traffic (publications per second counted on the graph; the baseline publishes these):')
    print('| module | publishers | of them sending | messages/s out | subscriptions |\n|---|---|---|---|---|')
    for name in names:
        publishers = traffic.publishers[name]
        print(f'| {name} | {len(publishers)} | {sum(e.rate > 0 for e in publishers)} | '
              f'{sum(e.rate for e in publishers):.1f} | {len(traffic.subscriptions[name])} |')
    if traffic.unattributed:
        print(f'({traffic.unattributed} messages on shared topics not told apart; left out)')
    print('\n| process | robot CPU % | robot PSS MB | raw rclpy CPU % | raw rclpy PSS MB '
          '| raw rclpy, EventsExecutor CPU % | raw rclpy, EventsExecutor PSS MB |\n|---|---|---|---|---|---|---|')
    robot_names = [name for name in names if name != CLIENT]
    for name in robot_names:
        where = next((f' (in container {c})' for c, members in groups.items() if name in members), '')
        print(f'| {name}{where} | {cell(robot.get(name))} | {cell(plain.get(name))} | {cell(events.get(name))} |')
    for name, members in groups.items():
        print(f'| container {name}: {", ".join(members)} | {cell(robot.get(name))} | | |')
    # A contained module's row is its thread's CPU, already in its container's: not counted again.
    processes = [name for name in robot if name != CLIENT and not any(name in m for m in groups.values())]

    def total(usage: dict[str, Usage], among: list[str]) -> str:
        return (f'{sum(usage[n].cpu for n in among if n in usage):.1f} | '
                f'{sum(usage[n].pss for n in among if n in usage):.0f}')

    print(f'| **total ({len(processes)} processes; baseline {len(robot_names)})** | {total(robot, processes)} | '
          f'{total(plain, robot_names)} | {total(events, robot_names)} |')
    print(f'| {CLIENT} client (not in the total) | {cell(robot.get(CLIENT))} | {cell(plain.get(CLIENT))} | '
          f'{cell(events.get(CLIENT))} |')
    print('(load average as each window began: ' + ', '.join(f'{k} {v:.2f}' for k, v in LOADS.items()) + ')')
    for note in notes:
        print(f'footprint: {note}')
    for pid in left:
        print(f'footprint: pid {pid} was left running: killed')
    return 1 if left else 0


if __name__ == '__main__':
    sys.exit(main())
