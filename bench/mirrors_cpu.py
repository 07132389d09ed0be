"""Benchmark: what the standard mirrors cost the dummies, unwatched and watched, in one run (issue 39).

config/pluto's dummies (base, laser, wrist, DMU, GPS; noise on) run under the MCP, the robot
standing.  Each dummy's CPU time (user + system, /proc/<pid>/stat) is measured over ``--seconds``
twice: first with nobody on the standard topics (since the mirrors are sent only while watched,
they cost nothing then), then with one rclpy node subscribed to every standard topic they offer
(LaserScan, Odometry and the ground truth, Imu, NavSatFix, the sonar and bumper Range rings,
BatteryState, JointState, /clock), as RViz or a recorder would be.  The difference is what the
mirrors cost while someone looks, and what an unwatched robot saves.

Usage: ``python bench/mirrors_cpu.py [--seconds 30]``.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import shutil
import sys
import tempfile
import time
from typing import Any

ROOT = pathlib.Path(__file__).resolve().parents[1]
DUMMIES = [('dummy_base', 'PlutoBase'), ('dummy_sick', 'PlutoLaser'), ('dummy_wrist', 'PlutoWrist'),
           ('dummy_dmu', 'PlutoDMU'), ('dummy_gps', 'PlutoGPS')]


def cpu_seconds(pid: int, tid: int | None = None) -> float:
    """User + system CPU seconds of process ``pid``, or of its thread ``tid``."""
    stat = pathlib.Path(f'/proc/{pid}/stat' if tid is None else f'/proc/{pid}/task/{tid}/stat')
    fields = stat.read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def topics() -> dict[str, Any]:
    """Every standard topic config/pluto's dummies offer, with its message type."""
    from nav_msgs.msg import Odometry
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import BatteryState, Imu, JointState, LaserScan, NavSatFix, Range
    return {'/PlutoLaser/scan': LaserScan, '/PlutoBase/odom': Odometry,
            '/PlutoBase/ground_truth/odom': Odometry, '/PlutoBase/sonar': Range, '/PlutoBase/bumpers': Range,
            '/PlutoBase/battery': BatteryState, '/PlutoDMU/imu': Imu, '/PlutoGPS/fix': NavSatFix,
            '/PlutoWrist/joint_states': JointState, '/clock': Clock}


def measure(pids: dict[str, int], seconds: float, spin: Any) -> dict[str, float]:
    """% of one core per dummy over ``seconds``, ``spin(timeout)`` run meanwhile."""
    start = {name: cpu_seconds(pid) for name, pid in pids.items()}
    began = time.monotonic()
    while time.monotonic() - began < seconds:
        spin(0.1)
    elapsed = time.monotonic() - began
    return {name: 100 * (cpu_seconds(pid) - start[name]) / elapsed for name, pid in pids.items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=30.0)
    args = parser.parse_args()
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through env.sh (DDS on loopback only)')
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from wurde_testing import ChildProcess, claim_domain_id, find_executable
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    work = pathlib.Path(tempfile.mkdtemp(prefix='wurde-mirrors-cpu-'))
    for name in ('sim-config.xml', 'map.xml'):
        shutil.copy(ROOT / 'config' / 'pluto' / name, work / name)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(work), WURDE_LOG_DIRECTORY=str(work))
    children = {name: ChildProcess([find_executable('wurde_drivers', exe), '-n', name], env=env)
                for exe, name in DUMMIES}
    context = Context()
    rclpy.init(context=context, domain_id=claim.domain_id)
    node = rclpy.create_node('mirrors_cpu', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    received = {'count': 0}

    def count(_: Any) -> None:
        received['count'] += 1

    try:
        pids = {name: child.process.pid for name, child in children.items()}
        time.sleep(10.0)                                           # discovery and start-up settle
        idle = measure(pids, args.seconds, time.sleep)
        for topic, kind in topics().items():
            node.create_subscription(kind, topic, count, 10)
        deadline = time.monotonic() + 60
        while received['count'] < 100:                            # matched and flowing
            if time.monotonic() > deadline:
                raise SystemExit('bench: the standard topics did not flow within 60 s')
            executor.spin_once(timeout_sec=0.1)
        received['count'] = 0
        watched = measure(pids, args.seconds, lambda t: executor.spin_once(timeout_sec=t))
        rate = received['count'] / args.seconds
    finally:
        executor.shutdown()
        node.destroy_node()
        context.try_shutdown()
        for child in children.values():
            child.stop()
        claim.release()
    print('| dummy | CPU % of one core, nobody on the standard topics | the same, all of them watched |\n|---|---|---|')
    for name in pids:
        print(f'| {name} | {idle[name]:.1f} | {watched[name]:.1f} |')
    print(f'| all five | {sum(idle.values()):.1f} | {sum(watched.values()):.1f} |')
    print(f'(standard messages received while watched: {rate:.0f} per second; {args.seconds:.0f} s each)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
