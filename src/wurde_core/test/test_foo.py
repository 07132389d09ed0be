"""FooServer and FooClient behave as in the guide (1.1.2), as installed executables."""

from __future__ import annotations

import os
import pathlib
import re

from wurde_testing import ChildProcess


def executable(name: str) -> str:
    for prefix in os.environ['AMENT_PREFIX_PATH'].split(os.pathsep):
        path = pathlib.Path(prefix) / 'lib' / 'wurde_core' / name
        if path.is_file():
            return str(path)
    raise AssertionError(f'{name} is not installed under lib/wurde_core')


def test_foo_client_prints_info_and_every_value_the_server_sends(ros_domain: int) -> None:
    with ChildProcess([executable('foo_client')]) as client:
        with ChildProcess([executable('foo_server')]) as server:
            client.expect('Info: MaxRange 8.0 angleMin 0.0 angleMax 3.141592653589793')
            values = [client.expect('Val ') for _ in range(6)]
            assert server.stop() == 0
        assert client.stop() == 0
    numbers = [float(re.search(r'Val (\S+)', line).group(1)) for line in values]
    # Queue mode on both sides: consecutive values, none lost (the client may join after 0).
    assert numbers == [numbers[0] + i for i in range(6)]
    stamps = [float(re.search(r'Timestamp: (\S+)', line).group(1)) for line in values]
    assert all(0.1 < b - a < 0.5 for a, b in zip(stamps, stamps[1:]))  # set_sleep(0.2)


def test_name_override_and_help(ros_domain: int) -> None:
    with ChildProcess([executable('foo_server'), '-h']) as helped:
        assert helped.process.wait(timeout=30) == 0
        helped.stop()
    assert '-r  registration mode' in helped.stdout and 'WURDE module FooServer' in helped.stdout
    with ChildProcess([executable('foo_server'), '-x']) as wrong:
        assert wrong.process.wait(timeout=30) == 2
        wrong.stop()
    assert 'option -x not recognized' in wrong.stderr and 'usage:' in wrong.stderr
