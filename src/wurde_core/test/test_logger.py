"""The Logger: levels, the global functions, files, and logging over the network."""

from __future__ import annotations

import pathlib
from collections.abc import Callable

import pytest

from conftest import until
from wurde_core import CommsManager, Logger, g_warn
from wurde_core import logger as logger_module
from wurde_core.interfaces import robot_object_class
from wurde_core.ros_adaptor import take_stamped


@pytest.fixture(autouse=True)
def fresh_global(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(logger_module, '_global', None)
    for name in ('WURDE_LOG_LEVEL', 'WURDE_LOG_DIRECTORY'):
        monkeypatch.delenv(name, raising=False)


def test_level_filter_and_global_functions(capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    g_warn('before any logger')
    assert '[WARN] before any logger' in capsys.readouterr().err
    log = Logger('Lg', use_syslog=False)
    monkeypatch.setenv('WURDE_LOG_LEVEL', 'warn')
    assert log.info_msg('quiet') is False
    assert log.error('loud') is True
    g_warn('through the global logger')
    err = capsys.readouterr().err
    assert '[ERROR] Lg: loud' in err and 'quiet' not in err
    assert '[WARN] Lg: through the global logger' in err


def test_log_directory_from_configuration(tmp_path: pathlib.Path,
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv('WURDE_LOG_DIRECTORY', str(tmp_path))
    log = Logger('Filed', stderr=False, use_syslog=False)
    log.notice('kept on disk')
    log.close()
    assert '[NOTICE] kept on disk' in (tmp_path / 'Filed.log').read_text()


def test_messages_travel_to_a_consumer_of_the_log_stream(manager: CommsManager) -> None:
    log = Logger('Net', stderr=False, use_syslog=False)
    manager.register_supplier(log)
    reader = robot_object_class('LoggerTransport')('log/Net')
    reader.set_queue_mode(True)
    manager.register_consumer(reader)
    until(manager, lambda: log.peers() > 0, what='match')
    log.fatal('the sky fell')
    until(manager, reader.new_data, what='log record')
    reader.get_next_data()
    assert (reader.data.level, reader.data.message) == (5, 'the sky fell')
    assert reader.data.source == 'Tester'


def _rosout(manager: CommsManager) -> Callable[[], list[tuple[int, str]]]:
    """A /rosout reader for this test's node: each call returns everything seen so far."""
    from rcl_interfaces.msg import Log
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    subscription = manager.node.create_subscription(Log, '/rosout', lambda _: None, qos)
    found: list[tuple[int, str]] = []

    def read() -> list[tuple[int, str]]:
        found.extend((message.level, message.msg) for message, _ in take_stamped(subscription))
        return found
    return read


def test_messages_reach_rosout(manager: CommsManager) -> None:
    from rcl_interfaces.msg import Log
    log = Logger('Rosout', stderr=False, use_syslog=False)
    manager.register_supplier(log)
    rosout = _rosout(manager)
    log.error('seen by every ROS 2 tool')
    until(manager, lambda: (Log.ERROR, 'seen by every ROS 2 tool') in rosout(), what='the message on /rosout')
    assert (Log.ERROR, 'seen by every ROS 2 tool') in rosout()


def test_one_logger_sends_every_severity_to_rosout(manager: CommsManager) -> None:
    """rclpy refuses a second severity from one call site; each level must still get through."""
    from rcl_interfaces.msg import Log
    log = Logger('Levels', stderr=False, use_syslog=False)
    manager.register_supplier(log)
    rosout = _rosout(manager)
    log.notice('first a notice')
    log.warn('then a warning')
    log.error('then an error')
    log.notice('and a notice again')
    until(manager, lambda: (Log.INFO, 'and a notice again') in rosout(), what='the four messages on /rosout')
    assert [m for m in rosout() if m[1] != ''][-4:] == [
        (Log.INFO, 'first a notice'), (Log.WARN, 'then a warning'), (Log.ERROR, 'then an error'),
        (Log.INFO, 'and a notice again')]
