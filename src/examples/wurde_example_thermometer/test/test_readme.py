"""The manual's examples about defining and running an interface work as written."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess

from wurde_testing.manual import section

ROOT = pathlib.Path(__file__).resolve().parents[4]
PACKAGE = pathlib.Path(__file__).resolve().parents[1]


def block(heading: str, language: str) -> str:
    """The first ```language block of the manual's section ``heading`` (docs/interfaces.md,
    docs/setup.md)."""
    match = re.compile(rf'```{language}\n(.*?)```', re.S).search(section(heading))
    assert match, f'no {language} block in {heading!r}'
    return match.group(1)


def test_cmake_snippet_is_what_the_example_package_does() -> None:
    cmake = (PACKAGE / 'CMakeLists.txt').read_text()
    for line in block('Adding an interface in your own package', 'cmake').strip().splitlines():
        assert line in cmake, line


def test_shell_snippet_runs_supplier_and_consumer(ros_domain: int) -> None:
    script = block('A shell for running things by hand', 'bash')
    env = dict(os.environ, ROS_DOMAIN_ID=str(ros_domain))
    result = subprocess.run(['bash', '-c', script], cwd=ROOT, env=env, capture_output=True,
                            text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    assert 'received 5 of 5 readings' in result.stdout
