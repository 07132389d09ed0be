#!/usr/bin/env python3
"""Figures on the package code's docstrings, for the rules in docs/style.md ("Docstrings").

Reports the module docstrings longer than :data:`MAX_MODULE_LINES`, the docstrings and comments
that tell a dated incident (a date, a make-test run, a CI run: commit messages hold those), and
the share of public functions with parameters whose docstring documents each one (``:param``).
Used by ``src/wurde_interfaces/test/test_docstrings.py``; run it to see the figures.
"""

from __future__ import annotations

import ast
import dataclasses
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: A module docstring says what the module is and why in about a screen at most.
MAX_MODULE_LINES = 25
#: Incidents and one-off measurements: a date, a numbered make-test run, a fresh-clone or CI run.
INCIDENT = re.compile(r'\b20\d\d-[01]\d-[0-3]\d\b|\bmake test r\d+|\bfresh[- ]clone\b|\bCI of [0-9a-f]{7}')


@dataclasses.dataclass
class Report:
    """What :func:`report` found."""

    long_modules: list[tuple[str, int]] = dataclasses.field(default_factory=list)
    incidents: list[str] = dataclasses.field(default_factory=list)
    public_functions: int = 0
    documented_functions: int = 0
    undocumented: list[str] = dataclasses.field(default_factory=list)

    @property
    def documented_share(self) -> float:
        return self.documented_functions / max(self.public_functions, 1)


def package_sources(root: pathlib.Path = ROOT) -> list[pathlib.Path]:
    """The packages' Python code (not their tests)."""
    return sorted(p for p in (root / 'src').rglob('*.py')
                  if 'test' not in p.relative_to(root / 'src').parts[1:-1])


def _public_functions(tree: ast.Module) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
    """Module-level functions and methods of module-level classes whose names (and class's) are
    public."""
    found: list[ast.FunctionDef | ast.AsyncFunctionDef] = []
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith('_'):
            found.append(node)
        elif isinstance(node, ast.ClassDef) and not node.name.startswith('_'):
            found += [f for f in node.body if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                      and (not f.name.startswith('_') or f.name == '__init__')]
    return found


def _parameters(function: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    args = function.args
    names = [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs]
    return [n for n in names if n not in ('self', 'cls') and not n.startswith('_')]


def _documents(docstring: str, parameter: str) -> bool:
    return re.search(rf':param {re.escape(parameter)}:', docstring) is not None


def report(paths: list[pathlib.Path] | None = None, root: pathlib.Path = ROOT) -> Report:
    """The figures for ``paths`` (default: every package source)."""
    result = Report()
    for path in paths if paths is not None else package_sources(root):
        text = path.read_text()
        name = str(path.relative_to(root))
        tree = ast.parse(text, filename=name)
        doc = ast.get_docstring(tree, clean=False)
        if doc and doc.count('\n') + 1 > MAX_MODULE_LINES:
            result.long_modules.append((name, doc.count('\n') + 1))
        for number, line in enumerate(text.splitlines(), 1):
            if INCIDENT.search(line):
                result.incidents.append(f'{name}:{number}: {line.strip()}')
        for function in _public_functions(tree):
            parameters = _parameters(function)
            if not parameters:
                continue
            result.public_functions += 1
            docstring = ast.get_docstring(function) or ''
            if all(_documents(docstring, p) for p in parameters):
                result.documented_functions += 1
            else:
                result.undocumented.append(f'{name}:{function.lineno}: {function.name}')
    return result


def main() -> int:
    found = report()
    print(f'module docstrings over {MAX_MODULE_LINES} lines: {len(found.long_modules)}')
    for name, lines in sorted(found.long_modules, key=lambda item: -item[1]):
        print(f'  {lines:4d} {name}')
    print(f'dated incidents in the code: {len(found.incidents)}')
    for line in found.incidents:
        print(f'  {line}')
    print(f'public functions with parameters: {found.public_functions}; each parameter documented '
          f'(:param): {found.documented_functions} ({100 * found.documented_share:.0f} %)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
