"""Every import is declared where a user installs from, and nothing is declared that nothing imports.

A package's code (everything outside its ``test/``) needs each third-party or ROS module it imports
as an ``exec_depend`` (or ``depend``) in its package.xml; its tests need it as a ``test_depend`` or
an ``exec_depend``.  Third-party modules must also be in ``requirements.in`` (what ``make build``
installs) and in the README's build-from-apt lines (the apt packages, or the pip line for what
Ubuntu does not package).  Imports are read from the source with :mod:`ast`, so an import inside a
function counts as much as one at the top.
"""
import ast
import functools
import importlib.metadata
import os
import pathlib
import re
import sys

import pytest
from wurde_idl.safe_xml import parse_file
from wurde_testing.manual import section

ROOT = pathlib.Path(__file__).resolve().parents[3]
PACKAGES = sorted(path.parent for path in (ROOT / 'src').glob('**/package.xml'))

# Python packages a workspace package installs beside its own name.
PROVIDED_BY = {'wurde_idl': 'wurde_interfaces', 'wurde_testing': 'wurde_interfaces'}
# Distributions whose rosdep key is not python3-<name>, and those Ubuntu 24.04 does not package
# (the README installs them with pip).
ROSDEP_KEY = {'pyserial': 'python3-serial', 'python-can': 'python3-can', 'pyyaml': 'python3-yaml',
              'opencv-python-headless': 'python3-opencv', 'mcap-ros2-support': 'python3-mcap-ros2',
              'foxglove-sdk': 'python3-foxglove'}
PIP_ONLY = {'mcap', 'mcap-ros2-support', 'rosbags', 'foxglove-sdk'}
# requirements.in lines that no source imports on purpose: the ROS wheels, the build tools.
TOOLING = re.compile(r'^(ros-jazzy-.*|colcon-.*|cmake|ruff|mypy)$')   # build and lint tools, run not imported


def _python_files(package: pathlib.Path):
    """The package's Python sources: .py files and scripts/ without a suffix; setup.py is build-time."""
    for path in package.rglob('*'):
        if not path.is_file() or path.name == 'setup.py' or '__pycache__' in path.parts:
            continue
        if path.suffix == '.py' or (path.parent.name == 'scripts' and not path.suffix):
            yield path


def _imports(path: pathlib.Path) -> set[str]:
    """Top-level names of the absolute imports in one file."""
    names = set()
    for node in ast.walk(ast.parse(path.read_bytes(), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name.split('.')[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split('.')[0])
    return names - set(sys.stdlib_module_names)


def _local_names(package: pathlib.Path) -> set[str]:
    """Modules a package's own files provide (its Python package, test helpers, cmake scripts)."""
    return {path.stem for path in package.rglob('*.py')} | {
        path.name for path in package.rglob('*') if path.is_dir() and (path / '__init__.py').exists()}


def _depends(package: pathlib.Path) -> tuple[set[str], set[str]]:
    """(exec keys, test keys) of a package.xml; ``depend`` counts for both."""
    root = parse_file(package / 'package.xml', root_tag='package')
    keys = {tag: {element.text.strip() for element in root.iter(tag)}
            for tag in ('depend', 'exec_depend', 'test_depend', 'build_export_depend')}
    exec_keys = keys['depend'] | keys['exec_depend']
    return exec_keys, exec_keys | keys['test_depend']


@functools.cache
def _workspace_names() -> dict[str, str]:
    """Workspace package names, and the Python packages they install, to the package providing them."""
    names = {parse_file(package / 'package.xml', root_tag='package').findtext('name'): None for package in PACKAGES}
    names = {name: name for name in names}
    names.update(PROVIDED_BY)
    return names


@functools.cache
def _is_ros_package(name: str) -> bool:
    """A ROS package of the underlay (the venv's ament prefix or /opt/ros): share/<name>/package.xml."""
    prefixes = os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep)
    return any((pathlib.Path(prefix) / 'share' / name / 'package.xml').is_file() for prefix in prefixes if prefix)


@functools.cache
def _distribution(module: str) -> str | None:
    """The PyPI distribution (lower case) installing a top-level module, or None for a ROS one."""
    found = _all_distributions().get(module)
    return found[0].lower() if found else None


@functools.cache
def _all_distributions() -> dict[str, list[str]]:
    return importlib.metadata.packages_distributions()


def _rosdep_key(distribution: str) -> str:
    return ROSDEP_KEY.get(distribution, f'python3-{distribution}')


def _requirement_names() -> set[str]:
    lines = (ROOT / 'requirements.in').read_text().splitlines()
    return {re.split(r'[=<>\[ ]', line.strip())[0].lower() for line in lines
            if line.strip() and not line.startswith('#')}


def _needed(package: pathlib.Path) -> dict[str, set[str]]:
    """For each import of a package's files: which of its files need it, split into code and tests."""
    local = _local_names(package)
    workspace = _workspace_names()
    needed: dict[str, set[str]] = {}
    for path in _python_files(package):
        kind = 'test' if path.relative_to(package).parts[0] == 'test' else 'exec'
        for name in _imports(path) - local:
            if workspace.get(name) == package.name:
                continue
            needed.setdefault(f'{kind}:{name}', set()).add(str(path.relative_to(ROOT)))
    return needed


def _key_of(module: str) -> str:
    workspace = _workspace_names()
    if module in workspace:
        return workspace[module]
    if _is_ros_package(module):
        return module
    distribution = _distribution(module)
    assert distribution, f'{module} is imported but no installed distribution or ROS package provides it'
    return _rosdep_key(distribution)


@pytest.mark.parametrize('package', PACKAGES, ids=[package.name for package in PACKAGES])
def test_every_import_is_in_package_xml(package):
    exec_keys, test_keys = _depends(package)
    missing = []
    for need, files in sorted(_needed(package).items()):
        kind, module = need.split(':')
        key = _key_of(module)
        if key not in (exec_keys if kind == 'exec' else test_keys):
            depend = 'exec_depend' if kind == 'exec' else 'test_depend'
            missing.append(f'<{depend}>{key}</{depend}> (import {module}: {sorted(files)[0]})')
    assert not missing, f'{package.name}/package.xml lacks: ' + '; '.join(missing)


def test_every_third_party_import_is_in_requirements_and_nothing_else_is():
    requirements = _requirement_names()
    imported = set()
    for package in PACKAGES:
        for need in _needed(package):
            module = need.split(':')[1]
            if module in _workspace_names() or _is_ros_package(module):
                continue
            distribution = _distribution(module)
            if distribution:
                imported.add(distribution)
    assert not imported - requirements, f'requirements.in lacks {sorted(imported - requirements)}'
    declared = {name for name in requirements if not TOOLING.match(name)}
    # zstandard and websockets are imported too; what is left over is installed for nothing.
    unused = declared - imported
    assert not unused, f'requirements.in lists what nothing imports: {sorted(unused)}'


def test_the_readme_apt_lines_install_every_declared_python_dependency():
    text = section('Building with ROS 2 Jazzy from apt (Ubuntu 24.04)')
    block = re.search(r'```bash\n(.*?)```', text, re.S).group(1).replace('\\\n', ' ')
    apt = set(re.findall(r'\bpython3-[\w-]+', ' '.join(line for line in block.splitlines() if 'apt' in line)))
    pip = set(' '.join(line.split('pip install', 1)[1] for line in block.splitlines() if 'pip install' in line).split())
    keys = set()
    for package in PACKAGES:
        exec_keys, test_keys = _depends(package)
        keys |= {key for key in exec_keys | test_keys if key.startswith('python3-')}
    by_key = {_rosdep_key(name): name for name in PIP_ONLY}
    missing = [key for key in sorted(keys)
               if (by_key[key] not in pip if key in by_key else key not in apt)]
    assert not missing, f"the apt build lines (docs/setup.md) lack {missing}"
