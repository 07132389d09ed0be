"""One module's traffic in raw rclpy, doing no work: the baseline of ``bench/footprint.py``.

A plain rclpy node (no WURDE) named after the module, with the module's publishers and
subscriptions as ``bench/footprint.py`` found them on the robot's graph (same topics, message
types and QoS), publishing on timers at the rates measured there.  What it publishes is one
message of each topic taken from the robot (deserialized once; serialized again at every
publication, as a node publishing its own message does); what it receives is deserialized and
dropped.  A transient-local topic the module published nothing on while it was counted (the WURDE
info channels, ``/tf_static``, ``/map``) is published once at the start, so that it holds what the
module's holds.  The spec (JSON, written by the benchmark) gives for each module::

    {"publishers": [{"topic", "type", "qos", "sample"}...], "subscriptions": [{"topic", "type", "qos"}...],
     "timers": [[RATE_HZ, [publisher index, ...]], ...]}

Prints ``baseline ready NAME`` once its entities exist, and spins (``--executor default``: rclpy's
SingleThreadedExecutor, as ``rclpy.spin``; ``events``: ``rclpy.experimental.EventsExecutor``, in
one-second ``spin_until_future_complete`` calls: see :func:`main`) until SIGINT.  Run by the benchmark, inside env.sh.

Usage: ``python bench/footprint_baseline.py --spec SPEC.json --node NAME [--executor default|events]``.
"""

from __future__ import annotations

import argparse
import base64
import importlib
import json
import sys
from typing import Any

import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.task import Future

def message_type(name: str) -> Any:
    """The Python class of ``pkg/msg/Type``."""
    package, _, kind = name.split('/')
    return getattr(importlib.import_module(f'{package}.msg'), kind)


def qos(spec: dict[str, Any]) -> QoSProfile:
    """A QoS profile from the spec's ``{"reliability", "durability", "depth"}``."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=int(spec['depth']),
                      reliability=(ReliabilityPolicy.RELIABLE if spec['reliability'] == 'reliable'
                                   else ReliabilityPolicy.BEST_EFFORT),
                      durability=(DurabilityPolicy.TRANSIENT_LOCAL if spec['durability'] == 'transient_local'
                                  else DurabilityPolicy.VOLATILE))


def build(node: Any, spec: dict[str, Any]) -> None:
    """The module's publishers, subscriptions and timers on ``node``."""
    publishers: list[tuple[Any, Any]] = []
    for entry in spec['publishers']:
        kind = message_type(entry['type'])
        publisher = node.create_publisher(kind, entry['topic'], qos(entry['qos']))
        sample = entry.get('sample')
        message = deserialize_message(base64.b64decode(sample), kind) if sample else kind()
        publishers.append((publisher, message))
    for entry in spec['subscriptions']:
        node.create_subscription(message_type(entry['type']), entry['topic'], lambda _message: None,
                                 qos(entry['qos']))
    timed = {index for _, indices in spec['timers'] for index in indices}
    for index, entry in enumerate(spec['publishers']):
        if index not in timed and entry['qos']['durability'] == 'transient_local' and entry.get('sample'):
            publishers[index][0].publish(publishers[index][1])
    for rate, indices in spec['timers']:
        batch = [publishers[index] for index in indices]

        def tick(batch: list[tuple[Any, Any]] = batch) -> None:
            for publisher, message in batch:
                publisher.publish(message)

        node.create_timer(1.0 / rate, tick)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--spec', required=True, help='the JSON spec of every module')
    parser.add_argument('--node', required=True, help="the module's name (its entry in the spec)")
    parser.add_argument('--executor', choices=('default', 'events'), default='default')
    args = parser.parse_args()
    with open(args.spec) as file:
        spec = json.load(file)[args.node]
    rclpy.init()
    node = rclpy.create_node(args.node)
    if args.executor == 'events':
        from rclpy.experimental import EventsExecutor
        executor = EventsExecutor()
    else:
        executor = SingleThreadedExecutor()
    try:
        build(node, spec)
        executor.add_node(node)
        print(f'baseline ready {args.node}', flush=True)
        if args.executor == 'events':
            # rclpy 7.1.5's EventsExecutor.spin() (and spin_until_future_complete without a timeout)
            # keeps a core busy while idle and does not return on SIGINT; with a timeout it sleeps
            # until an event and runs every event within it in C++, and SIGINT ends it.
            never = Future()
            while rclpy.ok():
                executor.spin_until_future_complete(never, timeout_sec=1.0)
        else:
            executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
