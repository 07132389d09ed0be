"""The module side of the MCP protocol: -r and -l capability reports, ASSIGNED streams."""

from __future__ import annotations

import pytest

from conftest import HERE, until
from wurde_core import CommsManager, ConnectionStrategy, RunState
from wurde_core.interfaces import Foo, robot_object_class
from wurde_testing import ChildProcess, find_executable

McpRequest = robot_object_class('McpRequest')


def foo_server() -> str:
    return find_executable('wurde_core', 'foo_server')


def test_registration_mode_reports_capabilities_to_the_mcp_and_exits(manager) -> None:
    mcp = McpRequest('mcp')
    mcp.set_queue_mode(True)
    manager.register_supplier(mcp)
    with ChildProcess([foo_server(), '-r']) as module:
        until(manager, mcp.new_request, what='capability report')
        assert module.process.wait(timeout=30) == 0
        module.stop()
    mcp.get_next_request()
    report = mcp.requests
    assert report.kind.get_value() == 2
    assert report.module.get_value() == 'FooServer'
    assert list(zip(report.provided_interfaces.get_value(), report.provided_streams.get_value())) \
        == [('Foo', 'Bar'), ('LoggerTransport', 'log/FooServer')]
    assert 'supplies Foo Bar' in module.stdout
    assert 'capabilities of FooServer sent to the MCP' in module.stdout


def test_name_override_reaches_the_report(manager) -> None:
    mcp = McpRequest('mcp')
    mcp.set_queue_mode(True)
    manager.register_supplier(mcp)
    with ChildProcess([foo_server(), '-r', '-n', 'OtherFoo']) as module:
        until(manager, mcp.new_request, what='capability report')
        assert module.process.wait(timeout=30) == 0
    mcp.get_next_request()
    assert mcp.requests.module.get_value() == 'OtherFoo'


@pytest.mark.parametrize('strategy', [ConnectionStrategy.ASSIGNED, ConnectionStrategy.AUTO])
def test_assigned_consumer_gets_its_stream_from_the_mcp(manager, strategy) -> None:
    """A fake MCP (this process) answers an ASSIGNED/AUTO request; the peer then receives data."""
    mcp = McpRequest('mcp')
    mcp.set_queue_mode(True)
    manager.register_supplier(mcp)
    foo = Foo('assigned_stream')
    manager.register_supplier(foo)
    script = HERE / 'assigned_client.py'
    with ChildProcess([str(script), strategy.name]) as client:
        until(manager, mcp.new_request, what='assignment request')
        mcp.get_next_request()
        ask = mcp.requests
        assert ask.kind.get_value() == 0
        assert ask.strategy.get_value() == strategy
        assert (ask.module.get_value(), ask.interface.get_value(), ask.object.get_value()) == \
            ('AssignedClient', 'Foo', 'BarClient')
        answer = mcp.info
        answer.request_id.set_value(ask.request_id.get_value())
        answer.module.set_value('AssignedClient')
        answer.object.set_value('BarClient')
        answer.stream.set_value('assigned_stream')
        answer.success.set_value(True)
        mcp.publish_info()
        client.expect('CONNECTED assigned_stream')
        until(manager, lambda: foo.peers() > 0, what='client subscribed')
        foo.data.ranges = [42.0]
        assert foo.publish_data()
        client.expect('VALUE 42.0')
    assert manager.state == RunState.RUN


def test_list_capabilities_keeps_running(manager) -> None:
    mcp = McpRequest('mcp')
    mcp.set_queue_mode(True)
    manager.register_supplier(mcp)
    with ChildProcess([foo_server(), '-l']) as module:
        until(manager, mcp.new_request, what='capability report')
        module.expect('supplies Foo Bar')
        module.expect('capabilities of FooServer sent to the MCP')
        assert module.process.poll() is None  # -l lists and goes on running
        assert module.stop() == 0


def test_normal_strategy_connects_at_once_and_asks_the_mcp_to_start_the_supplier(manager) -> None:
    mcp = McpRequest('mcp')
    mcp.set_queue_mode(True)
    manager.register_supplier(mcp)
    other = CommsManager('NormalClient')
    try:
        other.set_no_sleep()
        foo = Foo(ConnectionStrategy.NORMAL, 'Bar')
        other.register_consumer(foo)
        assert foo.is_connected() and foo.stream == 'Bar'
        until(other, lambda: other._mcp.obj.peers() > 0,
              what='MCP matched')
        other._mcp.request_start(foo)  # the first one may have gone before the match
        until(manager, mcp.new_request, what='start request')
        mcp.get_next_request()
        assert (mcp.requests.kind.get_value(), mcp.requests.object.get_value(),
                mcp.requests.strategy.get_value()) == (1, 'Bar', ConnectionStrategy.NORMAL)
    finally:
        other.clean_up()
