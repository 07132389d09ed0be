"""FooServer and FooClient behave as in the guide (1.1.2), as installed executables."""

from __future__ import annotations

import re

from wurde_testing import ChildProcess, find_executable


def test_foo_client_prints_info_and_every_value_the_server_sends(ros_domain: int) -> None:
    with ChildProcess([find_executable('wurde_core', 'foo_client')]) as client:
        with ChildProcess([find_executable('wurde_core', 'foo_server')]) as server:
            client.expect('Info: MaxRange 8.0 angleMin 0.0 angleMax 3.141592653589793')
            values = [client.expect('Val ') for _ in range(6)]
            assert server.stop() == 0
        assert client.stop() == 0
    numbers = [float(re.search(r'Val (\S+)', line).group(1)) for line in values]
    # Queue mode on both sides: consecutive values, none lost (the client may join after 0).
    assert numbers == [numbers[0] + i for i in range(6)]
    stamps = [float(re.search(r'Timestamp: (\S+)', line).group(1)) for line in values]
    assert all(b - a >= 0.19 for a, b in zip(stamps, stamps[1:]))  # set_sleep(0.2)


def test_name_override_and_help(ros_domain: int) -> None:
    with ChildProcess([find_executable('wurde_core', 'foo_server'), '-h']) as helped:
        assert helped.process.wait(timeout=30) == 0
        helped.stop()
    assert '-r  registration mode' in helped.stdout and 'WURDE module FooServer' in helped.stdout
    with ChildProcess([find_executable('wurde_core', 'foo_server'), '-x']) as wrong:
        assert wrong.process.wait(timeout=30) == 2
        wrong.stop()
    assert 'option -x not recognized' in wrong.stderr and 'usage:' in wrong.stderr
