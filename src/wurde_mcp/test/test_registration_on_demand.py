"""Suppliers asked for during the MCP's registration pass (real CommsManager, no processes until
the pass is over).

A consumer that asks for its assigned stream while every internal module is on its -r run got
the supplier started a second time: the pass then waited its whole timeout for that process to
exit, and stopped it (seen in a CI log of pluto_motion's test_guide_avoider).  The answer during
the pass is the stream, and the supplier starts with the others on activation.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from mcp_fixture import worker, write_config
from wurde_core import CommsManager, ConnectionStrategy
from wurde_mcp.config import read_mcp_config, read_mcp_mappings
from wurde_mcp.supervisor import Supervisor

MAPPING = '<connect module="Reader">\n<input interface="Foo" source="W_out" object="FooClient"/>\n</connect>'


@pytest.fixture
def supervisor(tmp_path, ros_domain: int) -> Iterator[Supervisor]:
    config_path, mappings_path = write_config(tmp_path, worker('W'), MAPPING)
    config = read_mcp_mappings(mappings_path, read_mcp_config(config_path))
    manager = CommsManager('RegistrationTest')
    manager.set_no_heartbeat()
    watched = Supervisor(manager, config, log_directory=str(tmp_path))
    watched.modules['W'].supplies = [('Foo', 'W_out')]      # as its -r report says
    try:
        yield watched
    finally:
        watched.quit_all(wait_s=10.0)
        watched.close()
        manager.clean_up()


def test_an_assignment_during_the_registration_pass_starts_nothing(supervisor: Supervisor) -> None:
    supervisor.registering = True
    assert supervisor.streams.assign('Reader', 'Foo', 'FooClient', ConnectionStrategy.ASSIGNED) == \
        (True, 'W_out', '')
    module = supervisor.modules['W']
    assert module.process is None and not module.wanted


def test_after_the_pass_an_assignment_starts_the_supplier_on_demand(supervisor: Supervisor) -> None:
    """The on-demand start itself is kept (guide 6.1: the MCP starts a module's suppliers)."""
    supervisor.registering = False
    assert supervisor.streams.assign('Reader', 'Foo', 'FooClient', ConnectionStrategy.ASSIGNED)[0]
    module = supervisor.modules['W']
    assert module.wanted and module.process is not None
