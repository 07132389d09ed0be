"""The package code keeps docs/style.md's docstring rules (figures: tools/docstring_report.py)."""

from __future__ import annotations

import importlib.util
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
#: Packages whose every public function documents its parameters: what users program against.
FULLY_DOCUMENTED = ('src/wurde_core/wurde_core', 'src/wurde_interfaces/wurde_idl')
#: The share of public functions with parameters that document each one, in every package.
LEAST_SHARE = 0.25
PACKAGES = ('wurde_core', 'wurde_interfaces', 'wurde_mcp', 'wurde_drivers', 'pluto_nav', 'pluto_motion')


def _tool() -> object:
    spec = importlib.util.spec_from_file_location('docstring_report', ROOT / 'tools' / 'docstring_report.py')
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module            # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


TOOL = _tool()


def test_module_docstrings_are_at_most_a_screen() -> None:
    found = TOOL.report()  # type: ignore[attr-defined]
    assert not found.long_modules, '\n'.join(f'{name}: {lines} lines' for name, lines in found.long_modules)


def test_no_incident_stories_in_the_code() -> None:
    found = TOOL.report()  # type: ignore[attr-defined]
    assert not found.incidents, '\n'.join(found.incidents)


@pytest.mark.parametrize('folder', FULLY_DOCUMENTED)
def test_the_user_api_documents_every_parameter(folder: str) -> None:
    paths = sorted((ROOT / folder).rglob('*.py'))
    found = TOOL.report(paths)  # type: ignore[attr-defined]
    assert found.public_functions > 0
    assert not found.undocumented, '\n'.join(found.undocumented)


@pytest.mark.parametrize('package', PACKAGES)
def test_a_quarter_of_every_package_documents_its_parameters(package: str) -> None:
    paths = [p for p in TOOL.package_sources() if p.relative_to(ROOT / 'src').parts[0] == package]  # type: ignore[attr-defined]
    found = TOOL.report(paths)  # type: ignore[attr-defined]
    assert found.public_functions > 0
    assert found.documented_share >= LEAST_SHARE, (
        f'{package}: {found.documented_functions} of {found.public_functions} '
        f'({100 * found.documented_share:.0f} %)')


def test_the_tool_finds_what_breaks_a_rule(tmp_path: pathlib.Path) -> None:
    source = tmp_path / 'src' / 'pkg' / 'pkg' / 'mod.py'
    source.parent.mkdir(parents=True)
    source.write_text('"""' + 'line\n' * 30 + '"""\n# a fresh-clone run saw this\n'
                      'def f(a, b):\n    """Do it.\n\n    :param a: one\n    """\n'
                      'def g(a):\n    """:param a: one"""\n')
    found = TOOL.report(root=tmp_path)  # type: ignore[attr-defined]
    assert [lines for _, lines in found.long_modules] == [31]
    assert len(found.incidents) == 1
    assert (found.public_functions, found.documented_functions) == (2, 1)
