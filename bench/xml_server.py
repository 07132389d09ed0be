"""Benchmark: the xmlServer at 10 clients (issue 15), against a raw rclpy subscriber in the same run.

This process supplies ``Localization/Dead-Reckoning`` at ``--rate`` Hz, the pose's x the message's
sequence number, and starts a real ``xml_server`` process (free port, 127.0.0.1).

1. ``gets``: 10 clients (threads, one socket each) ask ``var odoPose.pose`` as fast as the server
   answers, for ``--seconds``: gets per second, all clients together, and the p99 round trip.
2. ``push latency``: each client asks ``<varpush struct=odoPose i=1 cmd="var odoPose.pose"/>``;
   latency = a pushed line's arrival at a client - the publication of the pose it carries (one
   monotonic clock).  Beside it, a raw rclpy node in a child process subscribes to the same topic
   and reports each message's arrival: the floor the middleware sets; the server adds its loop turn
   (up to 10 ms) and the socket.

Usage: ``make bench-xml`` (or ``python bench/xml_server.py`` inside ``source env.sh``).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import threading
import time

CLIENTS = 10
#: The first poses of each measurement are not counted (matching, first callbacks).
WARM_UP_S = 1.0
STREAM = 'Localization/Dead-Reckoning'


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(math.ceil(q * len(ordered))) - 1)]


def _raw_subscriber() -> None:
    """Child: a raw rclpy node printing ``seq arrival`` (monotonic) for each message."""
    import rclpy
    from rclpy.executors import ExternalShutdownException
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from wurde_core import topic
    from wurde_interfaces.msg import LocalizationPoseData
    rclpy.init()
    node = rclpy.create_node('raw_pose_reader')

    def heard(message: LocalizationPoseData) -> None:
        print(f'{int(round(message.pose.x))} {time.monotonic():.6f}', flush=True)

    node.create_subscription(LocalizationPoseData, topic(STREAM, 'data'), heard,
                             QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
    print('raw ready', flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


class Publisher:
    """The Dead-Reckoning supplier: ``publish()`` sends the next sequence number, remembered with
    its monotonic publication time."""

    def __init__(self) -> None:
        from wurde_core import CommsManager
        from wurde_core.interfaces import LocalizationPose
        self.manager = CommsManager('XmlBench')
        self.manager.set_no_sleep()
        self.pose = LocalizationPose(STREAM)
        self.manager.register_supplier(self.pose)
        self.sent: dict[int, float] = {}
        self.seq = 0

    def publish(self) -> None:
        from wurde_core import Pose3D
        self.seq += 1
        self.pose.data.pose = Pose3D(float(self.seq), 0.0, 0.0, 0.0, 0.0, 0.0)
        self.sent[self.seq] = time.monotonic()
        self.pose.publish_data()

    def run(self, seconds: float, rate: float, stop: threading.Event | None = None) -> None:
        end = time.monotonic() + seconds
        next_at = time.monotonic()
        while time.monotonic() < end and not (stop and stop.is_set()):
            if time.monotonic() >= next_at:
                self.publish()
                next_at += 1.0 / rate
            self.manager.step()
            self.manager.wait(max(0.0, min(0.005, next_at - time.monotonic())))


def gets(port: int, seconds: float) -> tuple[int, list[float]]:
    """Total gets and every round trip (ms) of 10 clients asking as fast as they are answered."""
    from wurde_mcp.xml_server import XmlClient
    counts = [0] * CLIENTS
    trips: list[list[float]] = [[] for _ in range(CLIENTS)]
    start = threading.Barrier(CLIENTS + 1)

    def client(i: int) -> None:
        with XmlClient(port=port, timeout=10.0) as c:
            start.wait()
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                t = time.perf_counter()
                c.get('odoPose.pose')
                trips[i].append((time.perf_counter() - t) * 1000.0)
                counts[i] += 1

    threads = [threading.Thread(target=client, args=(i,)) for i in range(CLIENTS)]
    for t in threads:
        t.start()
    start.wait()
    for t in threads:
        t.join()
    return sum(counts), [v for trip in trips for v in trip]


def pushes(port: int, publisher: Publisher, seconds: float, rate: float) -> list[float]:
    """Push latencies (ms) at 10 clients while the publisher runs ``seconds``."""
    from wurde_mcp.xml_server import XmlClient
    arrivals: list[list[tuple[int, float]]] = [[] for _ in range(CLIENTS)]
    ready = threading.Barrier(CLIENTS + 1)
    stop = threading.Event()

    def client(i: int) -> None:
        with XmlClient(port=port, timeout=10.0) as c:
            c.request('<varpush struct=odoPose i=1 cmd="var odoPose.pose"/>')
            ready.wait()
            while not stop.is_set():
                for line in c.lines(timeout=0.2):
                    if line.get('') == 'var' and 'x' in line:
                        arrivals[i].append((int(round(float(line['x']))), time.monotonic()))

    threads = [threading.Thread(target=client, args=(i,)) for i in range(CLIENTS)]
    for t in threads:
        t.start()
    ready.wait()
    first = publisher.seq + 1 + int(rate * WARM_UP_S)
    publisher.run(seconds, rate)
    publisher.run(0.5, rate)                    # let the last ones arrive
    stop.set()
    for t in threads:
        t.join()
    return [(at - publisher.sent[seq]) * 1000.0 for arrived in arrivals for seq, at in arrived
            if seq >= first and seq in publisher.sent]


def raw(publisher: Publisher, seconds: float, rate: float) -> list[float]:
    """The raw rclpy subscriber's latencies (ms) for the same stream."""
    child = subprocess.Popen([sys.executable, __file__, '--raw'], stdout=subprocess.PIPE, text=True)
    lines: list[str] = []
    try:
        stdout = child.stdout
        assert stdout is not None
        if stdout.readline().strip() != 'raw ready':
            raise SystemExit('bench: the raw subscriber did not start')
        reader = threading.Thread(target=lambda: lines.extend(iter(stdout.readline, '')), daemon=True)
        reader.start()
        deadline = time.monotonic() + 30
        while publisher.pose.peers('data') < 2 and time.monotonic() < deadline:   # the server and it
            publisher.manager.step()
            publisher.manager.wait(0.05)
        first = publisher.seq + 1 + int(rate * WARM_UP_S)
        publisher.run(seconds, rate)
        publisher.run(0.5, rate)
    finally:
        child.terminate()
        try:
            child.wait(timeout=10)
        except subprocess.TimeoutExpired:   # seen once: still in a write to its pipe
            child.kill()
            child.wait()
    values = []
    for line in lines:
        seq, at = line.split()
        if int(seq) >= first and int(seq) in publisher.sent:
            values.append((float(at) - publisher.sent[int(seq)]) * 1000.0)
    return values


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=20.0)
    parser.add_argument('--rate', type=float, default=50.0, help='poses per second')
    parser.add_argument('--raw', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.raw:
        _raw_subscriber()
        return 0
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('bench: run it through `make bench-xml` or env.sh (DDS on loopback only)')
    from wurde_testing import claim_domain_id, find_executable
    claim = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    print(f'xmlServer benchmark, ROS_DOMAIN_ID={claim.domain_id}, {os.cpu_count()} cores, {CLIENTS} clients')
    publisher = Publisher()
    server = subprocess.Popen([find_executable('wurde_mcp', 'xml_server'), '-p', '0'], stdout=subprocess.PIPE,
                              text=True)
    try:
        assert server.stdout is not None
        line = server.stdout.readline()
        match = re.search(r'127\.0\.0\.1:(\d+)', line)
        if not match:
            raise SystemExit(f'bench: xml_server did not start: {line!r}')
        port = int(match.group(1))
        deadline = time.monotonic() + 30
        while not publisher.pose.peers('data') and time.monotonic() < deadline:
            publisher.publish()
            publisher.manager.step()
            publisher.manager.wait(0.05)
        stop = threading.Event()
        feeder = threading.Thread(target=publisher.run, args=(args.seconds + 5, args.rate, stop))
        feeder.start()
        try:
            total, trips = gets(port, args.seconds)
        finally:
            stop.set()
            feeder.join()
        print(f'\n{"var odoPose.pose, 10 clients at once":44} {"gets/s":>9} {"p50 ms":>9} {"p99 ms":>9}')
        print(f'  {"xml_server process":42} {total / args.seconds:9.0f} {statistics.median(trips):9.2f} '
              f'{_percentile(trips, 0.99):9.2f}')
        xml = pushes(port, publisher, args.seconds, args.rate)
        floor = raw(publisher, args.seconds, args.rate)
    finally:
        server.terminate()
        server.wait(timeout=10)
        publisher.manager.clean_up()
    print(f'\n{"pose published -> line at the client":44} {"n":>6} {"p50 ms":>9} {"p99 ms":>9}')
    for name, values in (('xml_server varpush, 10 clients', xml), ('raw rclpy subscriber (floor)', floor)):
        if not values:
            print(f'  {name:42} no samples')
            continue
        print(f'  {name:42} {len(values):6d} {statistics.median(values):9.2f} {_percentile(values, 0.99):9.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
