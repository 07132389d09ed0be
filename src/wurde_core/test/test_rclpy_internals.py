"""rclpy's internals are reached from one file, wurde_core/ros_adaptor.py (issue 42): no other
module of any package uses an rclpy object's ``.handle`` or imports ``rclpy.impl``, so an rclpy
change is mended in one place."""

from __future__ import annotations

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[3]
ADAPTOR = ROOT / 'src' / 'wurde_core' / 'wurde_core' / 'ros_adaptor.py'


def _package_sources() -> list[pathlib.Path]:
    """Every Python file of the packages' code (not their tests)."""
    return [path for path in sorted((ROOT / 'src').rglob('*.py'))
            if '/test/' not in path.as_posix() and path.name != 'setup.py']


def test_only_the_adaptor_touches_rclpy_internals() -> None:
    sources = _package_sources()
    assert ADAPTOR in sources and len(sources) > 100
    reached = []
    for path in sources:
        if path == ADAPTOR:
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Attribute) and node.attr == 'handle':
                reached.append(f'{path.relative_to(ROOT)}:{node.lineno}: .handle')
            elif isinstance(node, ast.ImportFrom) and (node.module or '').startswith('rclpy.impl'):
                reached.append(f'{path.relative_to(ROOT)}:{node.lineno}: from {node.module}')
            elif isinstance(node, ast.Import) and any(a.name.startswith('rclpy.impl') for a in node.names):
                reached.append(f'{path.relative_to(ROOT)}:{node.lineno}: import rclpy.impl')
    assert reached == [], '\n'.join(reached)


def test_the_adaptor_does_reach_them() -> None:
    """The check above looks at what the adaptor really uses."""
    tree = ast.parse(ADAPTOR.read_text())
    assert any(isinstance(n, ast.Attribute) and n.attr == 'handle' for n in ast.walk(tree))
