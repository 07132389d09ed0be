"""pytest fixtures for tests that use real rclpy and real DDS.

Load from a package's ``conftest.py`` with ``pytest_plugins = ['wurde_testing.fixtures']``.
Importing this module already forces DDS discovery onto loopback for the test process and its
children (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator

import pytest

from .domain import claim_domain_id

os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ.pop('ROS_STATIC_PEERS', None)


@pytest.fixture
def ros_domain(monkeypatch: pytest.MonkeyPatch) -> Iterator[int]:
    """A ``ROS_DOMAIN_ID`` of this test's own, set in the environment for it and its children.

    :param monkeypatch: pytest's, which restores the environment after the test.
    """
    claim = claim_domain_id()
    monkeypatch.setenv('ROS_DOMAIN_ID', str(claim.domain_id))
    monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    try:
        yield claim.domain_id
    finally:
        claim.release()


@pytest.fixture
def rclpy_context(ros_domain: int) -> Iterator[object]:
    """A fresh, initialised rclpy context in the test's own domain; shut down afterwards.

    :param ros_domain: the test's domain id (the fixture above).
    """
    import rclpy
    from rclpy.context import Context

    context = Context()
    rclpy.init(context=context, domain_id=ros_domain)
    try:
        yield context
    finally:
        context.try_shutdown()


# -- the fast lane (`make test-fast`) ---------------------------------------------------------------
def pytest_addoption(parser: pytest.Parser) -> None:
    """Add ``--fast``, the fast lane.

    :param parser: pytest's option parser.
    """
    parser.addoption('--fast', action='store_true',
                     help='the fast lane: only the tests that need neither DDS (the ros_domain fixture) nor '
                          'other processes (pytest.mark.process); starting a process fails the test')


def pytest_configure(config: pytest.Config) -> None:
    """Declare the ``process`` marker.

    :param config: pytest's configuration.
    """
    config.addinivalue_line('markers', 'process: the test starts other processes (not in the fast lane)')


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """With ``--fast``, deselect the tests that use ``ros_domain`` or are marked ``process``.

    :param config: pytest's configuration.
    :param items: the collected tests, changed in place.
    """
    if not config.getoption('--fast'):
        return
    slow = [item for item in items
            if 'ros_domain' in getattr(item, 'fixturenames', ()) or item.get_closest_marker('process')]
    if slow:
        config.hook.pytest_deselected(items=slow)
        items[:] = [item for item in items if item not in set(slow)]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item: pytest.Item) -> Iterator[None]:
    """With ``--fast``, a fixture that starts a process fails the test.

    :param item: the test being set up.
    """
    with _processes_refused(item.config.getoption('--fast')):
        yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item: pytest.Item) -> Iterator[None]:
    """With ``--fast``, a test that starts a process fails.

    :param item: the test being run.
    """
    with _processes_refused(item.config.getoption('--fast')):
        yield


@contextlib.contextmanager
def _processes_refused(refused: bool) -> Iterator[None]:
    """In the fast lane a test (or its fixtures) that starts a process fails, saying how to mark
    it: what the lane promises is checked, not assumed.  Imports are not guarded (ctypes'
    find_library runs ldconfig once)."""
    if not refused:
        yield
        return
    import subprocess

    def refuse(*_args: object, **_kwargs: object) -> None:
        raise RuntimeError('the fast lane starts no processes: mark this test (or its module) '
                           'with pytest.mark.process')

    saved = subprocess.Popen.__init__, os.fork
    subprocess.Popen.__init__ = refuse  # type: ignore[method-assign]  # the lane's guard
    os.fork = refuse  # type: ignore[assignment]  # the lane's guard (pty.fork, multiprocessing)
    try:
        yield
    finally:
        subprocess.Popen.__init__, os.fork = saved  # type: ignore[method-assign]
