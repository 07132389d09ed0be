"""Benchmark: the localModule's CPU with odometry at 50 Hz (issue 11: below 5 % of a core).

The simulated Pluto runs with the base's odometry at 50 Hz (the DMU at 50 Hz, a scan every 190 ms,
the wrist at 20 Hz); ``local_module`` fuses them all.  Its CPU time (user + system, from
/proc/<pid>/stat) over ``--seconds`` of wall time, after a warm-up, is reported as a percentage of
one core, next to, in the same run, the dummy DMU's (a module that publishes one stream at 50 Hz)
and a raw rclpy node with the localModule's traffic and no estimation at all
(``bench/raw_rclpy_fusion.py``: per odometry message the same five publications), which shows
what the middleware alone costs at this rate.

Usage: ``make bench`` or ``python bench/local_module_cpu.py [--seconds 30]``.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

from lxml import etree

ROOT = pathlib.Path(__file__).resolve().parents[1]


def cpu_seconds(pid: int) -> float:
    fields = pathlib.Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=30.0)
    parser.add_argument('--rate', type=float, default=50.0, help='odometry rate (Hz)')
    args = parser.parse_args()
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through `make bench` or env.sh (DDS on loopback only)')
    from wurde_core import CommsManager
    from wurde_core.interfaces import LocalizationPose
    from wurde_testing import ChildProcess, claim_domain_id, find_executable
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    work = pathlib.Path(tempfile.mkdtemp(prefix='wurde-local-cpu-'))
    tree = etree.parse(str(ROOT / 'config' / 'pluto' / 'sim-config.xml'))
    tree.getroot().find('base').set('rate', str(args.rate))
    tree.write(str(work / 'sim-config.xml'))
    (work / 'map.xml').write_bytes((ROOT / 'config' / 'pluto' / 'map.xml').read_bytes())
    env = dict(os.environ, WURDE_CONFIG_DIR=str(work), WURDE_LOG_DIRECTORY=str(work))
    dummies = [('dummy_base', 'PlutoBase'), ('dummy_dmu', 'PlutoDMU'), ('dummy_sick', 'PlutoLaser'),
               ('dummy_wrist', 'PlutoWrist')]
    manager = CommsManager('LocalCpuBench')
    manager.set_no_sleep()
    poses = LocalizationPose('Localization/Dead-Reckoning')
    poses.set_queue_mode(True)
    manager.register_consumer(poses)
    processes = [ChildProcess([find_executable('wurde_drivers', exe), '-n', name], env=env) for exe, name in dummies]
    local = ChildProcess([find_executable('pluto_nav', 'local_module')], env=env)
    raw = subprocess.Popen([sys.executable, str(ROOT / 'bench' / 'raw_rclpy_fusion.py')], env=env,
                           stdout=subprocess.PIPE, text=True)
    try:
        assert raw.stdout is not None
        ready = raw.stdout.readline().split()
        if ready[:2] != ['raw', 'ready']:
            raise SystemExit('bench: the raw rclpy node found no odometry and IMU topics')
        count = 0
        deadline = time.monotonic() + 60
        while count < 50:                          # warm-up: the fusion is running
            manager.step()
            while poses.get_next_data():
                count += 1
            if time.monotonic() > deadline:
                raise SystemExit('bench: no dead reckoning from local_module within 60 s')
            manager.wait(0.05)
        dmu = processes[1].process.pid
        start = {pid: cpu_seconds(pid) for pid in (local.process.pid, dmu, raw.pid)}
        wall, count = time.monotonic(), 0
        while time.monotonic() - wall < args.seconds:
            manager.step()
            while poses.get_next_data():
                count += 1
            manager.wait(0.05)
        elapsed = time.monotonic() - wall
        used = {pid: cpu_seconds(pid) - start[pid] for pid in start}
    finally:
        manager.clean_up()
        raw.terminate()
        raw.wait(timeout=30)
        for process in (local, *processes):
            process.stop()
    print(f'| process | CPU (% of one core) over {elapsed:.0f} s |\n|---|---|')
    share = 100 * used[local.process.pid] / elapsed
    print(f'| local_module (odometry {args.rate:.0f} Hz, DMU 50 Hz, scans 5 Hz) | {share:.1f} |')
    print(f'| dummy_dmu (one stream at 50 Hz), for comparison | {100 * used[dmu] / elapsed:.1f} |')
    print(f'| raw rclpy node, the same traffic ({" and ".join(ready[2:])} in), no estimation | '
          f'{100 * used[raw.pid] / elapsed:.1f} |')
    print(f'dead-reckoning poses received: {count / elapsed:.1f} per second')
    return 0


if __name__ == '__main__':
    sys.exit(main())
