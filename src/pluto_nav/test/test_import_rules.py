"""pluto_nav imports only what docs/design.md's "Who may import whom" allows."""

import pathlib

from wurde_testing.imports import violations

SOURCE = pathlib.Path(__file__).resolve().parents[1] / 'pluto_nav'


def test_imports_follow_the_package_rules() -> None:
    assert SOURCE.is_dir()
    assert violations('pluto_nav', SOURCE) == []
