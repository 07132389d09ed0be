"""Every interface's Data and Info message crosses from one process to another over real DDS."""

from __future__ import annotations

import os
import pathlib
import time
from collections.abc import Iterator
from typing import Any

import pytest
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

import roundtrip_fill as rt
from wurde_idl import load_all
from wurde_testing import ChildProcess, claim_domain_id

HERE = pathlib.Path(__file__).parent
DEADLINE_S = 60.0

#: Every interface the issue names, from the WURDE guide and the Pluto document.
EXPECTED_INTERFACES = sorted([
    'BlobFinder', 'Bumper', 'Egomotion', 'FaceDetector', 'Foo', 'Heartbeat', 'ImageDisplay',
    'ImageTransport', 'LoggerTransport', 'McpRequest', 'NavigatorTransport',
    'ObstacleAvoiderTransport', 'Power', 'PTUnit', 'RangeFinder', 'SimpleControl',
    'SoundController', 'SynchroDrive', 'VisionControl', 'WallBuilder', 'VectorMoverTransport',
    'RobotDrive', 'ActuatorState', 'FVectorState', 'LocalizationPose', 'DMUState', 'GPS',
    'MapServer',                                    # CARMEN 5's map server (issue 13)
])


def ours() -> dict[str, dict[str, Any]]:
    return {n: d for n, d in load_all().items() if d['package'] == 'wurde_interfaces'}


def test_every_interface_is_installed() -> None:
    assert sorted(ours()) == EXPECTED_INTERFACES


@pytest.fixture(scope='module')
def received() -> Iterator[dict[tuple[str, str], Any]]:
    """Run the peer process once; collect what arrives from it on every topic."""
    claim = claim_domain_id()
    env = dict(os.environ, ROS_DOMAIN_ID=str(claim.domain_id),
               ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
               PYTHONPATH=f'{HERE}{os.pathsep}{os.environ.get("PYTHONPATH", "")}')
    context = Context()
    rclpy.init(context=context, domain_id=claim.domain_id)
    got: dict[tuple[str, str], Any] = {}
    try:
        node = rclpy.create_node('wurde_roundtrip_test', context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        wanted = []
        for name, desc in ours().items():
            for channel, message in (('data', desc['data_message']),
                                     ('info', desc['info_message'])):
                key = (name, channel)
                wanted.append(key)
                node.create_subscription(
                    rt.message_class(f'wurde_interfaces/{message}'), rt.topic(name, channel),
                    lambda msg, key=key: got.setdefault(key, msg), rt.QOS)
        with ChildProcess([str(HERE / 'roundtrip_peer.py')], env=env) as peer:
            deadline = time.monotonic() + DEADLINE_S
            while len(got) < len(wanted) and time.monotonic() < deadline:
                if peer.process.poll() is not None:
                    break
                executor.spin_once(timeout_sec=0.1)
            code = peer.stop()
        assert code in (0, -2), f'peer failed ({code}):\n{peer.stderr}'
        yield got
    finally:
        context.try_shutdown()
        claim.release()


@pytest.mark.process
@pytest.mark.parametrize('name', EXPECTED_INTERFACES)
@pytest.mark.parametrize('channel', ['data', 'info'])
def test_message_arrives_intact_in_another_process(
        received: dict[tuple[str, str], Any], name: str, channel: str) -> None:
    desc = ours()[name]
    message = desc['data_message'] if channel == 'data' else desc['info_message']
    assert (name, channel) in received, f'no {message} arrived within {DEADLINE_S} s'
    expected = rt.fill(rt.message_class(f'wurde_interfaces/{message}'), f'{name}.{channel}')
    assert received[(name, channel)] == expected
    assert received[(name, channel)].header.source == expected.header.source != ''
