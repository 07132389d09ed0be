"""Fixtures for the MCP tests."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import pytest

from mcp_fixture import Table
from xml_server_fixture import Start, running

pytest_plugins = ['wurde_testing.fixtures']


@pytest.fixture
def table(ros_domain: int) -> Iterator[Table]:
    """A reader of the MCP's module table, in this process and the test's domain."""
    reader = Table()
    try:
        yield reader
    finally:
        reader.close()


@pytest.fixture
def start() -> Iterator[Start]:
    """xmlServers the test starts (``start(**settings)``), stopped at the test's end."""
    with contextlib.ExitStack() as stack:
        yield lambda **kw: stack.enter_context(running(**kw))
