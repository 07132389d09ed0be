"""Benchmark: how fast the MCP notices and repairs failures, and what supervising costs.

Measured from a separate observer process, all on this machine (DDS on loopback, a domain of the
benchmark's own):

- SIGKILL of a managed module -> the MCP's table says DEAD (exit noticed) -> the new process's
  first heartbeat (back in Run), over several kills;
- SIGSTOP of a module -> the table says ZOMBIE (hang noticed), against the module's TTL;
- the MCP's CPU (% of one core) over 10 s while it supervises 20 modules, and per module.

Anchor (issue): nav2's lifecycle manager needs 4.0-4.2 s to notice a crash and then
re-transitions every node.  Usage: ``make bench`` or ``python bench/mcp_supervision.py``.
"""

from __future__ import annotations

import os
import pathlib
import signal
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
WORKER = HERE.parent / 'src' / 'wurde_mcp' / 'test' / 'worker.py'


def cpu_seconds(pid: int) -> float:
    with open(f'/proc/{pid}/stat') as handle:
        fields = handle.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def main() -> int:
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through `make bench` or env.sh (DDS on loopback only)')
    from wurde_core import CommsManager, StatusMode
    from wurde_core.interfaces import robot_object_class
    from wurde_core.mcp_client import control_stream
    from wurde_testing import claim_domain_id, find_executable
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    workdir = pathlib.Path(tempfile.mkdtemp(prefix='wurde-mcp-bench-'))
    modules = ''.join(f'<module name="W{i:02d}" binary="{WORKER}"><options>-n W{i:02d}</options>'
                      '</module>' for i in range(20))
    (workdir / 'c.xml').write_text(f'<mcp-config>{modules}</mcp-config>')
    (workdir / 'm.xml').write_text('<mcp-mappings/>')
    env = dict(os.environ, WURDE_LOG_DIRECTORY=str(workdir))
    mcp = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'mcp'), '-c',
                            str(workdir / 'c.xml'), '-m', str(workdir / 'm.xml'), '-a', '-k', '100'],
                           env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    manager = CommsManager('McpBench')
    manager.set_no_sleep()
    manager.set_no_heartbeat()
    table = robot_object_class('SimpleControl')(control_stream())
    table.set_queue_mode(True)
    manager.register_consumer(table)
    # Each kill hits a different module, so every restart is a first one (no back-off delay).
    victims = [f'W{i:02d}' for i in range(2, 7)]
    beats = {}
    for name in victims:
        beats[name] = robot_object_class('Heartbeat')(f'heartbeat/{name}')
        beats[name].set_queue_mode(True)
        manager.register_consumer(beats[name])
    rows: dict[str, tuple[StatusMode, int]] = {}

    def poll() -> None:
        manager.step()
        while table.get_next_data():
            d = table.data
            rows.update({n: (StatusMode(s), p) for n, s, p in
                         zip(d.module_names, d.module_status, d.module_pid)})

    def until(predicate, timeout: float = 60.0) -> float:
        deadline = time.monotonic() + timeout
        while not predicate():
            if time.monotonic() > deadline:
                raise SystemExit(f'bench: timed out; table {rows}')
            poll()
            manager.wait(0.001)
        return time.monotonic()

    try:
        until(lambda: len(rows) == 20 and all(s == StatusMode.ACTIVE for s, _ in rows.values()),
              timeout=120)
        time.sleep(1.0)
        cpu0, t0 = cpu_seconds(mcp.pid), time.monotonic()
        end = t0 + 10.0
        while time.monotonic() < end:
            poll()
            manager.wait(0.05)
        cpu_percent = 100 * (cpu_seconds(mcp.pid) - cpu0) / (time.monotonic() - t0)

        detect, back = [], []
        for name in victims:
            beat = beats[name]
            old = rows[name][1]
            while beat.get_next_data() or beat.get_next_info():
                pass
            start = time.monotonic()
            os.kill(old, signal.SIGKILL)
            detect.append(until(lambda: rows[name][0] != StatusMode.ACTIVE or
                                rows[name][1] != old) - start)

            def new_beat() -> bool:
                while beat.get_next_info():
                    pass
                fresh = False
                while beat.get_next_data():
                    fresh = beat.data.source == name and beat.info.pid.get_value() not in (0, old)
                return fresh
            back.append(until(new_beat) - start)
            until(lambda: rows[name][0] == StatusMode.ACTIVE)

        # The module's own start-up, for comparison: a worker started by hand, to its first beat.
        solo = robot_object_class('Heartbeat')('heartbeat/Solo')
        solo.set_queue_mode(True)
        manager.register_consumer(solo)
        startup = []
        for _ in range(3):
            start = time.monotonic()
            process = subprocess.Popen([sys.executable, str(WORKER), '-n', 'Solo'],
                                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            startup.append(until(solo.get_next_data) - start)
            process.send_signal(signal.SIGINT)
            process.wait(timeout=30)
            while solo.get_next_data() or solo.get_next_info():
                pass

        hang = []
        for name in ('W07', 'W08', 'W09'):
            pid = rows[name][1]
            start = time.monotonic()
            os.kill(pid, signal.SIGSTOP)
            hang.append(until(lambda: rows[name][0] == StatusMode.ZOMBIE or
                              rows[name][1] != pid) - start)
            until(lambda: rows[name][0] == StatusMode.ACTIVE and rows[name][1] != pid)
    finally:
        manager.clean_up()
        mcp.send_signal(signal.SIGINT)
        mcp.wait(timeout=60)
        claim.release()
    ttl = 1.0  # worker.py: set_sleep(0.5)
    print(f'MCP supervision, 20 worker modules, ROS_DOMAIN_ID={claim.domain_id}')
    print(f'{"measure":<44} {"median":>8} {"max":>8}')
    print(f'{"SIGKILL -> exit noticed (ms)":<44} {1000 * statistics.median(detect):>8.1f} '
          f'{1000 * max(detect):>8.1f}')
    print(f'{"SIGKILL -> new process heartbeat in Run (ms)":<44} '
          f'{1000 * statistics.median(back):>8.1f} {1000 * max(back):>8.1f}')
    print(f'{"module start-up alone, spawn -> heartbeat (ms)":<44} '
          f'{1000 * statistics.median(startup):>8.1f} {1000 * max(startup):>8.1f}')
    print(f'{"SIGSTOP -> zombie noticed (ms, TTL 1000)":<44} {1000 * statistics.median(hang):>8.1f} '
          f'{1000 * max(hang):>8.1f}')
    print(f'MCP CPU with 20 modules: {cpu_percent:.1f} % of a core '
          f'({cpu_percent / 20:.2f} % per module); anchor: nav2 lifecycle manager 4000-4200 ms '
          f'to notice a crash; TTL {ttl * 1000:.0f} ms')
    return 0


if __name__ == '__main__':
    sys.exit(main())
