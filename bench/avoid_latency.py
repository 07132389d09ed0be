"""Benchmark: the avoidModule's speed (issue 12, "How good it must be").

1. ``compute``: one avoid step for a 361-point scan, in this process, no ROS: the scan's points
   (:class:`pluto_motion.scan_points.Beams`), the goto's vector summation with the laser guard
   (cmdFlags 22) and, separately, the laser guard alone (cmdFlags 20).  Goal: 4.45 ms (nav2's
   collision monitor in C++); mean and p99 over a few thousand steps on scans raycast in a room
   with a box.
2. ``latency``: laser scan in -> drive command out through a real avoid_module process.  This
   process is the laser (a RangeFinder ``BenchLaser``, 361 beams, 20 Hz) and the driveModule (a
   supplier of ``drive/command`` that takes the avoidModule's requests).  The avoidModule runs a
   velocity command with laser protection, and each scan puts an obstacle at a distance of its own,
   so each scan's slowed speed is different and the drive command it causes is told apart from the
   loop's others: latency = the request's arrival - the scan's publication (one clock).  Goal:
   p99 <= 20 ms.  Beside it, in the same run, the same two streams through a raw rclpy relay node
   (scan callback -> publish), the floor the middleware sets.

Usage: ``make bench-avoid`` (or ``python bench/avoid_latency.py`` inside ``source env.sh``).
"""

from __future__ import annotations

import argparse
import math
import os
import pathlib
import statistics
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'src' / 'pluto_motion' / 'test'))      # goto_sim: the raycaster


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(math.ceil(q * len(ordered))) - 1)]


def compute(steps: int) -> dict[str, tuple[float, float]]:
    import numpy as np
    from goto_sim import LASER, box, raycast

    from pluto_motion.avoid_command import AvoidCommand, parse_command
    from pluto_motion.avoid_control import AvoidController

    walls = box(0, 0, 10, 6) + box(4.5, 2.5, 5.5, 3.5)
    rng = np.random.default_rng(1)
    poses = [(float(rng.uniform(1, 4)), float(rng.uniform(1, 5)), float(rng.uniform(-1, 1))) for _ in range(50)]
    scans = [raycast(walls, x + 0.2 * math.cos(t), y + 0.2 * math.sin(t), t + LASER.theta) for x, y, t in poses]
    results = {}

    def goto(flags: int) -> AvoidCommand:
        command = parse_command(flags, [0.5, 1.0], [8.5, 3.0])
        assert command is not None              # cmdFlags 2x: a goto, never a release
        return command

    for name, flags in (('goto + laser guard (22)', 22), ('laser guard alone (20)', 20)):
        control = AvoidController()
        control.accept(goto(flags), now=0.0)
        times = []
        for i in range(steps):
            pose, ranges = poses[i % len(poses)], scans[i % len(scans)]
            now = 0.01 * (i + 1)
            started = time.perf_counter()
            control.set_laser(list(ranges), LASER.points(ranges), now, now, pose)
            control.step(now, pose)
            times.append((time.perf_counter() - started) * 1000.0)
            if control.goto_code in (1, 2):
                control.accept(goto(flags), now=now)
        results[name] = (statistics.fmean(times), _percentile(times, 0.99))
    return results


def _scan_ranges(i: int) -> list[float]:
    """A scan with an obstacle straight ahead at a distance of its own (0.60 .. 0.99 m)."""
    ranges = [8.0] * 361
    ranges[175:186] = [0.6 + 0.001 * (i % 400)] * 11
    return ranges


def latency(seconds: float, rate: float) -> list[float]:
    from wurde_core import CommsManager, Time
    from wurde_core.interfaces import ActuatorState, FVectorState, RangeFinder
    from wurde_testing import ChildProcess, find_executable

    from pluto_motion.avoid_proxy import AvoidProxy

    work = pathlib.Path(tempfile.mkdtemp(prefix='wurde-avoid-bench-'))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(work), WURDE_LOG_DIRECTORY=str(work))
    manager = CommsManager('AvoidBench')
    manager.set_no_sleep()
    laser = RangeFinder('BenchLaser')
    laser.set_auto_timestamp(False)
    drive = ActuatorState('drive/command')
    drive.set_queue_mode(True)
    drive_status = FVectorState('drive/status')
    for obj in (laser, drive, drive_status):
        manager.register_supplier(obj)
    avoid = AvoidProxy(manager)
    info = laser.info
    info.max_range.set_value(8.0)
    info.x_offset.set_value(0.2)
    info.theta_offset.set_value(-math.pi / 2)
    info.theta_separation.set_value(math.pi / 360)
    sent: dict[float, float] = {}
    latencies: list[float] = []
    with ChildProcess([find_executable('pluto_motion', 'avoid_module'), '-L', 'BenchLaser'], env=env):
        laser.publish_info()
        deadline = time.monotonic() + 60
        while avoid.code is None and time.monotonic() < deadline:
            manager.step()
            avoid.update()
            manager.wait(0.05)
        if avoid.code is None:
            raise SystemExit('bench: the avoidModule was not heard within 60 s')
        period = 1.0 / rate
        next_scan = time.monotonic()
        next_command = 0.0
        end = time.monotonic() + seconds
        i = 0
        while time.monotonic() < end:
            now = time.monotonic()
            if now >= next_command:
                avoid.velocity(0.5, 0.0, laser=True)       # a hand command, renewed within 4 s
                next_command = now + 1.0
            if now >= next_scan:
                i += 1
                laser.data.ranges = _scan_ranges(i)
                laser.data.timestamp = Time(i * period)
                sent[round(0.6 + 0.001 * (i % 400), 6)] = time.perf_counter()
                laser.publish_data()
                next_scan += period
            manager.step()
            while drive.get_next_request():
                arrived = time.perf_counter()
                velocity = list(drive.requests.velocity.get_value())
                key = _key_of(velocity[0]) if velocity else None
                if key is not None and key in sent:
                    latencies.append((arrived - sent.pop(key)) * 1000.0)
            manager.wait(max(0.0, min(next_scan, next_command) - time.monotonic()))
    manager.clean_up()
    return latencies[5:]                                   # the first ones include discovery


def _key_of(tv: float) -> float | None:
    """The obstacle distance of the scan whose slowed speed is ``tv`` (the guard's inverse)."""
    from pluto_motion.laser_guard import GuardLimits
    g = GuardLimits()
    if tv <= 0.0:
        return None
    gap = tv / 0.5 * (g.slow - g.stop) + g.stop
    return round(gap + g.radius + g.margin - 0.2, 3)


def raw_relay(seconds: float, rate: float) -> list[float]:
    """The floor: a raw rclpy node relaying each RangeFinderData to an ActuatorStateInfo request
    topic, in a child process; the same measurement."""
    import subprocess
    child = subprocess.Popen([sys.executable, __file__, '--relay'])
    try:
        return _relay_client(seconds, rate)
    finally:
        child.terminate()
        child.wait(timeout=10)


def _qos():
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)


def _relay() -> None:
    import rclpy
    from rclpy.executors import ExternalShutdownException
    from wurde_interfaces.msg import ActuatorStateInfo, RangeFinderData
    rclpy.init()
    node = rclpy.create_node('raw_relay')
    out = node.create_publisher(ActuatorStateInfo, '/bench_raw/command', _qos())

    def relay(message: RangeFinderData) -> None:
        request = ActuatorStateInfo()
        request.velocity = [message.ranges[180], 0.0]
        out.publish(request)

    node.create_subscription(RangeFinderData, '/bench_raw/scan', relay, _qos())
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def _relay_client(seconds: float, rate: float) -> list[float]:
    import rclpy
    from wurde_interfaces.msg import ActuatorStateInfo, RangeFinderData
    rclpy.init()
    node = rclpy.create_node('raw_relay_client')
    scans = node.create_publisher(RangeFinderData, '/bench_raw/scan', _qos())
    sent: dict[float, float] = {}
    latencies: list[float] = []

    def back(message: ActuatorStateInfo) -> None:
        key = round(float(message.velocity[0]), 3)
        if key in sent:
            latencies.append((time.perf_counter() - sent.pop(key)) * 1000.0)

    node.create_subscription(ActuatorStateInfo, '/bench_raw/command', back, _qos())
    deadline = time.monotonic() + 30
    while scans.get_subscription_count() == 0 and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
    end = time.monotonic() + seconds
    next_scan, i = time.monotonic(), 0
    while time.monotonic() < end:
        if time.monotonic() >= next_scan:
            i += 1
            message = RangeFinderData(ranges=_scan_ranges(i))
            sent[round(0.6 + 0.001 * (i % 400), 3)] = time.perf_counter()
            scans.publish(message)
            next_scan += 1.0 / rate
        rclpy.spin_once(node, timeout_sec=max(0.0, next_scan - time.monotonic()))
    node.destroy_node()
    rclpy.shutdown()
    return latencies[5:]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--steps', type=int, default=3000)
    parser.add_argument('--seconds', type=float, default=30.0)
    parser.add_argument('--rate', type=float, default=20.0, help='scans per second')
    parser.add_argument('--relay', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.relay:
        _relay()
        return 0
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through `make bench-avoid` or env.sh (DDS on loopback only)')
    from wurde_testing import claim_domain_id
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    print(f'avoidModule benchmark, ROS_DOMAIN_ID={claim.domain_id}, {os.cpu_count()} cores')
    print(f'\n{"avoidance computation, 361-point scan":44} {"mean ms":>9} {"p99 ms":>9}  goal')
    for name, (mean, p99) in compute(args.steps).items():
        print(f'  {name:42} {mean:9.3f} {p99:9.3f}  p99 <= 4.45 ms: {"met" if p99 <= 4.45 else "NOT met"}')
    avoid = latency(args.seconds, args.rate)
    raw = raw_relay(args.seconds, args.rate)
    print(f'\n{"scan in -> drive command out":44} {"n":>5} {"p50 ms":>9} {"p99 ms":>9}  goal')
    for name, values in (('avoid_module process', avoid), ('raw rclpy relay (floor)', raw)):
        if not values:
            print(f'  {name:42} no samples')
            continue
        p50, p99 = statistics.median(values), _percentile(values, 0.99)
        goal = f'p99 <= 20 ms: {"met" if p99 <= 20.0 else "NOT met"}' if name.startswith('avoid') else ''
        print(f'  {name:42} {len(values):5d} {p50:9.2f} {p99:9.2f}  {goal}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
