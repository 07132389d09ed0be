"""Test helpers shared by every package of the suite (installed by wurde_interfaces).

- :func:`claim_domain_id`: a ``ROS_DOMAIN_ID`` no other test on this machine is using, so that
  tests in parallel packages and parallel CI runs never see each other's DDS traffic.
- :mod:`wurde_testing.fixtures`: pytest fixtures (load with ``pytest_plugins``) that keep DDS on
  loopback, give each test its own domain, and run rclpy with a fresh context per test.
- :mod:`wurde_testing.topics`: :func:`~wurde_testing.topics.latched`, a transient-local topic read late.
- :mod:`wurde_testing.parameters`: ``ros2 param list/get/set/dump`` through rclpy's parameter
  client (ros2cli is not on PyPI).
"""

from .domain import DomainClaim, claim_domain_id
from .process import ChildProcess, find_executable

__all__ = ['ChildProcess', 'DomainClaim', 'claim_domain_id', 'find_executable']
