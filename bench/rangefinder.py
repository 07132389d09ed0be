"""Benchmark: one RangeFinder stream (361 ranges) between two processes, received three ways.

1. ``wurde``    wurde_core: ``run_update`` with a Trigger, ``get_next_data`` in queue mode;
2. ``executor`` raw rclpy: a subscription callback, ``SingleThreadedExecutor.spin_once``;
3. ``take``     raw rclpy: ``take_message`` on the subscription in a tight loop (the fastest
                Python can go).

For each: throughput with the sender publishing as fast as it can, latency p50/p99 with the sender
at 100 Hz (header stamp to receipt, same clock), and the receiver's CPU with no traffic at all.
All in one run on this machine, DDS on loopback, a domain of the benchmark's own.

Usage: ``make bench`` (or ``python bench/rangefinder.py`` inside ``source env.sh``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

RANGES = 361
TOPIC_STREAM = 'bench_laser'


def _now_ns() -> int:
    return time.time_ns()


def sender(rate: float, seconds: float) -> None:
    """Publish RangeFinderData with wurde_core's topic and QoS; rate 0 means flat out."""
    import rclpy
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from wurde_interfaces.msg import RangeFinderData

    rclpy.init()
    node = rclpy.create_node('bench_sender')
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.VOLATILE)
    publisher = node.create_publisher(RangeFinderData, f'/wurde/{TOPIC_STREAM}/data', qos)
    message = RangeFinderData(ranges=[1.5] * RANGES)
    message.header.source = 'bench_sender'
    deadline = time.monotonic() + 20
    while publisher.get_subscription_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.5)  # let the receiver finish discovery on its side too
    end = time.monotonic() + seconds
    period = 1.0 / rate if rate else 0.0
    next_at = time.monotonic()
    sequence = 0
    started = time.monotonic()
    while time.monotonic() < end:
        sequence += 1
        stamp = _now_ns()
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(stamp, 1_000_000_000)
        message.header.sequence = sequence
        publisher.publish(message)
        if period:
            next_at += period
            delay = next_at - time.monotonic()
            if delay > 0:
                time.sleep(delay)
    print(json.dumps({'sent': sequence, 'rate': sequence / (time.monotonic() - started)}),
          flush=True)
    node.destroy_node()
    rclpy.shutdown()


def _latency_us(stamp) -> float:
    return (_now_ns() - (stamp.sec * 1_000_000_000 + stamp.nanosec)) / 1000.0


#: How long a receiver waits for the first message (discovery on a busy machine takes seconds).
FIRST_WAIT_S = 30.0


def _measuring(first: float | None, start: float, seconds: float, idle: bool) -> bool:
    """Whether to go on receiving: ``seconds`` from the first message (from the start when
    idle), waiting up to :data:`FIRST_WAIT_S` for that first message."""
    now = time.monotonic()
    if first is None and not idle:
        return now - start < FIRST_WAIT_S
    return now - (first or start) < seconds


def receiver(mode: str, seconds: float, idle: bool) -> dict:
    """Receive for ``seconds`` after the first message; report count, latencies and CPU."""
    latencies: list[float] = []
    count = 0
    first = None
    if mode == 'wurde':
        from wurde_core import CommsManager, Trigger
        from wurde_core.interfaces import RangeFinder
        manager = CommsManager('bench_receiver')
        manager.set_no_sleep()
        manager.set_no_heartbeat()
        laser = RangeFinder(TOPIC_STREAM)
        laser.set_queue_mode(True)
        manager.register_consumer(laser)
        manager.register_trigger(Trigger(laser))
        print('READY', flush=True)
        start = time.monotonic()
        cpu0 = time.process_time()
        while _measuring(first, start, seconds, idle):
            manager.run_update(timeout=0.2)
            while laser.get_next_data():
                if first is None:
                    first = time.monotonic()
                count += 1
                latencies.append(_latency_us(laser.data.ros_message().header.stamp))
        manager.clean_up()
    else:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from wurde_interfaces.msg import RangeFinderData
        rclpy.init()
        node = rclpy.create_node('bench_receiver')
        qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE)
        got: list = []
        subscription = node.create_subscription(RangeFinderData, f'/wurde/{TOPIC_STREAM}/data',
                                                got.append, qos)
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        print('READY', flush=True)
        start = time.monotonic()
        cpu0 = time.process_time()
        take = subscription.handle.take_message
        while _measuring(first, start, seconds, idle):
            if mode == 'executor':
                executor.spin_once(timeout_sec=0.2)
                messages = got[:]
                got.clear()
            else:
                result = take(RangeFinderData, False)
                messages = [result[0]] if result is not None else []
            for message in messages:
                if first is None:
                    first = time.monotonic()
                count += 1
                latencies.append(_latency_us(message.header.stamp))
        node.destroy_node()
        rclpy.shutdown()
    elapsed = time.monotonic() - (first or start)
    cpu = time.process_time() - cpu0
    return {'mode': mode, 'count': count, 'elapsed': elapsed,
            'rate': count / elapsed if elapsed else 0.0,
            'p50_us': statistics.median(latencies) if latencies else None,
            'p99_us': statistics.quantiles(latencies, n=100)[98] if len(latencies) >= 100 else None,
            'cpu_percent': 100.0 * cpu / max(elapsed, 1e-9), 'idle': idle}


def run_pair(mode: str, rate: float, seconds: float) -> dict:
    here = os.path.abspath(__file__)
    receiver_process = subprocess.Popen([sys.executable, here, 'receive', mode, str(seconds)],
                                        stdout=subprocess.PIPE, text=True)
    assert receiver_process.stdout is not None
    assert receiver_process.stdout.readline().strip() == 'READY'
    sender_process = subprocess.Popen([sys.executable, here, 'send', str(rate), str(seconds + 2)],
                                      stdout=subprocess.PIPE, text=True)
    output, _ = receiver_process.communicate(timeout=seconds + 60)
    sent, _ = sender_process.communicate(timeout=60)
    result = json.loads(output.strip().splitlines()[-1])
    result['sender_rate'] = json.loads(sent.strip().splitlines()[-1])['rate']
    return result


def median_run(mode: str, rate: float, seconds: float, runs: int) -> dict:
    """The run with the median receive rate out of ``runs``."""
    results = sorted((run_pair(mode, rate, seconds) for _ in range(runs)), key=lambda r: r['rate'])
    return results[len(results) // 2]


def idle_cpu(mode: str, seconds: float) -> float:
    """Receiver CPU (% of a core) over ``seconds`` with no sender at all."""
    here = os.path.abspath(__file__)
    process = subprocess.run([sys.executable, here, 'idle', mode, str(seconds)],
                             capture_output=True, text=True, timeout=seconds + 60, check=True)
    return json.loads(process.stdout.strip().splitlines()[-1])['cpu_percent']


def main() -> int:
    parser = argparse.ArgumentParser(description='RangeFinder stream benchmark')
    sub = parser.add_subparsers(dest='command')
    for name in ('receive', 'idle'):
        cmd = sub.add_parser(name)
        cmd.add_argument('mode', choices=['wurde', 'executor', 'take'])
        cmd.add_argument('seconds', type=float)
    send = sub.add_parser('send')
    send.add_argument('rate', type=float)
    send.add_argument('seconds', type=float)
    args = parser.parse_args()
    if args.command == 'send':
        sender(args.rate, args.seconds)
        return 0
    if args.command in ('receive', 'idle'):
        if args.command == 'idle' and args.mode == 'take':
            # A take loop has nothing to wait on: it spins at 100 % by construction.
            pass
        result = receiver(args.mode, args.seconds, args.command == 'idle')
        print(json.dumps(result), flush=True)
        return 0

    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through `make bench` or env.sh (DDS on loopback only)')
    from wurde_testing import claim_domain_id
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    rows = []
    for mode in ('wurde', 'executor', 'take'):
        flat = median_run(mode, 0.0, 3.0, 3)
        paced = run_pair(mode, 100.0, 5.0)
        idle = idle_cpu(mode, 3.0)
        rows.append((mode, flat, paced, idle))
    take_rate = next(r[1]['rate'] for r in rows if r[0] == 'take')
    executor_row = next(r for r in rows if r[0] == 'executor')
    print(f'RangeFinder, {RANGES} doubles, reliable, depth 1000, two processes, '
          f'ROS_DOMAIN_ID={claim.domain_id}')
    print('throughput: median of 3 runs of 3 s, sender flat out; latency: 5 s at 100 Hz; '
          'idle: 3 s, no sender')
    print(f'{"receiver":<10} {"msgs/s":>9} {"sent/s":>9} {"x take":>7} {"x exec":>7} '
          f'{"p50 us":>8} {"p99 us":>8} {"idle CPU %":>10}')
    for mode, flat, paced, idle in rows:
        print(f'{mode:<10} {flat["rate"]:>9.0f} {flat["sender_rate"]:>9.0f} '
              f'{flat["rate"] / take_rate:>7.2f} {flat["rate"] / executor_row[1]["rate"]:>7.2f} '
              f'{paced["p50_us"]:>8.0f} {paced["p99_us"]:>8.0f} {idle:>10.1f}')
    wurde = rows[0]
    print(f'latency wurde / executor: p50 {wurde[2]["p50_us"] / executor_row[2]["p50_us"]:.2f}, '
          f'p99 {wurde[2]["p99_us"] / executor_row[2]["p99_us"]:.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
