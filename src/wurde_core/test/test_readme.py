"""The README's wurde_core examples run as written."""

from __future__ import annotations

import pathlib
import re

from wurde_testing import ChildProcess

README = pathlib.Path(__file__).resolve().parents[3] / 'README.md'


def examples() -> dict[str, str]:
    """``<!-- example: name -->`` followed by a python block, by name."""
    text = README.read_text()
    found = dict(re.findall(r'<!-- example: (\w+) -->\n```python\n(.*?)```', text, re.S))
    assert {'foo_server', 'foo_client'} <= set(found), sorted(found)
    return found


def test_readme_foo_server_and_client_run_as_written(ros_domain: int,
                                                    tmp_path: pathlib.Path) -> None:
    paths = {}
    for name, code in examples().items():
        paths[name] = tmp_path / f'{name}.py'
        paths[name].write_text(code)
    with ChildProcess([str(paths['foo_client'])]) as client, \
            ChildProcess([str(paths['foo_server'])]) as server:
        client.expect('Info: MaxRange 8.0 angleMin 0.0 angleMax 3.141592653589793')
        first = float(client.expect('Val ').rsplit(' ', 1)[1])
        second = float(client.expect('Val ').rsplit(' ', 1)[1])
        assert second == first + 1
        assert server.stop() == 0
        assert client.stop() == 0
