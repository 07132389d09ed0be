"""pytest fixtures for tests that use real rclpy and real DDS.

Load from a package's ``conftest.py`` with ``pytest_plugins = ['wurde_testing.fixtures']``.
Importing this module already forces DDS discovery onto loopback for the test process and its
children (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``).
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest

from .domain import claim_domain_id

os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ.pop('ROS_STATIC_PEERS', None)


@pytest.fixture
def ros_domain(monkeypatch: pytest.MonkeyPatch) -> Iterator[int]:
    """A ``ROS_DOMAIN_ID`` of this test's own, set in the environment for it and its children."""
    claim = claim_domain_id()
    monkeypatch.setenv('ROS_DOMAIN_ID', str(claim.domain_id))
    monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    try:
        yield claim.domain_id
    finally:
        claim.release()


@pytest.fixture
def rclpy_context(ros_domain: int) -> Iterator[object]:
    """A fresh, initialised rclpy context in the test's own domain; shut down afterwards."""
    import rclpy
    from rclpy.context import Context

    context = Context()
    rclpy.init(context=context, domain_id=ros_domain)
    try:
        yield context
    finally:
        context.try_shutdown()
