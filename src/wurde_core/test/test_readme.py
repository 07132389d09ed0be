"""The manual's wurde_core examples (docs/programming.md) run as written."""

from __future__ import annotations

import pathlib

from wurde_testing import ChildProcess
from wurde_testing.manual import example


def test_readme_foo_server_and_client_run_as_written(ros_domain: int,
                                                    tmp_path: pathlib.Path) -> None:
    paths = {}
    for name in ('foo_client', 'foo_server'):
        paths[name] = tmp_path / f'{name}.py'
        paths[name].write_text(example(name, 'python'))
    with ChildProcess([str(paths['foo_client'])]) as client, \
            ChildProcess([str(paths['foo_server'])]) as server:
        client.expect('Info: MaxRange 8.0 angleMin 0.0 angleMax 3.141592653589793')
        first = float(client.expect('Val ').rsplit(' ', 1)[1])
        second = float(client.expect('Val ').rsplit(' ', 1)[1])
        assert second == first + 1
        assert server.stop() == 0
        assert client.stop() == 0
