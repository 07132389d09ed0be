"""Fixtures for the MCP tests."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from mcp_fixture import Table

pytest_plugins = ['wurde_testing.fixtures']


@pytest.fixture
def table(ros_domain: int) -> Iterator[Table]:
    """A reader of the MCP's module table, in this process and the test's domain."""
    reader = Table()
    try:
        yield reader
    finally:
        reader.close()
