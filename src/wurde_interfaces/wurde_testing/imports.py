"""The import rules of the suite (docs/design.md: "Who may import whom"), checked on the source tree.

``wurde_core`` imports ``wurde_interfaces`` and nothing else of ours; the MCP, drivers and Pluto
packages import ``wurde_core`` and talk to each other only through interfaces at run time
(``pluto_motion`` may use ``pluto_nav``'s loc proxy); codecs import neither rclpy nor wurde_core.
"""

from __future__ import annotations

import ast
import pathlib

#: Python top-level packages of the suite and the ROS package that ships each.
SUITE_MODULES = {
    'wurde_idl': 'wurde_interfaces', 'wurde_testing': 'wurde_interfaces',
    'wurde_interfaces': 'wurde_interfaces', 'wurde_core': 'wurde_core', 'wurde_mcp': 'wurde_mcp',
    'wurde_drivers': 'wurde_drivers', 'pluto_nav': 'pluto_nav', 'pluto_motion': 'pluto_motion',
}

#: ROS packages each package may import (besides itself).
ALLOWED = {
    'wurde_interfaces': {'wurde_interfaces'},
    'wurde_core': {'wurde_interfaces'},
    'wurde_mcp': {'wurde_interfaces', 'wurde_core'},
    'wurde_drivers': {'wurde_interfaces', 'wurde_core'},
    'pluto_nav': {'wurde_interfaces', 'wurde_core'},
    'pluto_motion': {'wurde_interfaces', 'wurde_core', 'pluto_nav'},
}


def imported_modules(path: pathlib.Path) -> set[str]:
    """Top-level module names imported by one Python file (relative imports left out).

    :param path: the file.
    """
    tree = ast.parse(path.read_text(), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name.split('.')[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split('.')[0])
    return found


def violations(package: str, source_dir: pathlib.Path) -> list[str]:
    """``file: imports X`` for every import of a suite package that ``package`` may not use.

    :param package: a key of :data:`ALLOWED` (``wurde_core``).
    :param source_dir: the directory whose ``*.py`` files are checked, recursively.
    """
    allowed = ALLOWED[package] | {package}
    problems = []
    for path in sorted(source_dir.rglob('*.py')):
        for module in sorted(imported_modules(path)):
            owner = SUITE_MODULES.get(module)
            if owner is not None and owner not in allowed:
                problems.append(f'{path}: imports {module} (package {owner})')
    return problems
