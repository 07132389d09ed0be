"""wurde_drivers imports only what docs/design.md's "Who may import whom" allows.

Package level: only wurde_interfaces and wurde_core of ours.  File level, following imports inside
the package to the end (a codec that imports a helper which imports rclpy breaks the rule too):
codecs import neither rclpy nor wurde_core; the simulator's world and raycaster (and its other
models) import no rclpy; nothing outside the simulator imports it, so a real driver never does.
"""

from __future__ import annotations

import ast
import pathlib
from collections.abc import Iterable

from wurde_testing.imports import violations

SOURCE = pathlib.Path(__file__).resolve().parents[1] / 'wurde_drivers'
PACKAGE = 'wurde_drivers'
DEVICES = ('sick', 'rflex', 'ptu', 'wrist', 'gps', 'dmu')
#: Simulator modules that run as ROS programs; the rest of ``sim`` is pure numpy.
SIM_PROGRAMS = ('wurde_drivers.sim.dummies', 'wurde_drivers.sim.tour', 'wurde_drivers.sim.loading')
ROS = ('rclpy', 'wurde_core')


def _module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(SOURCE.parent).with_suffix('').parts
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


MODULES = {_module_name(path): path for path in SOURCE.rglob('*.py')}


def _resolve(name: str) -> str | None:
    """The package module that ``name`` (a module or a name inside one) lives in, if any."""
    while name and name not in MODULES:
        name = name.rpartition('.')[0]
    return name or None


def direct_imports(module: str) -> set[str]:
    """Every module ``module`` imports, fully qualified (relative imports resolved)."""
    path = MODULES[module]
    base = module if path.name == '__init__.py' else module.rpartition('.')[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parent = '.'.join(base.split('.')[:len(base.split('.')) - node.level + 1])
                source = f'{parent}.{node.module}' if node.module else parent
            else:
                source = node.module or ''
            found.add(source)
            found.update(f'{source}.{alias.name}' for alias in node.names
                         if _resolve(f'{source}.{alias.name}') == f'{source}.{alias.name}')
    return found


def reachable(module: str) -> dict[str, str]:
    """Every module imported by ``module`` directly or through package modules -> the package
    module that imports it (to name the culprit in a failure)."""
    seen: dict[str, str] = {}
    todo = [module]
    done: set[str] = set()
    while todo:
        current = todo.pop()
        if current in done:
            continue
        done.add(current)
        for name in direct_imports(current):
            seen.setdefault(name, current)
            inner = _resolve(name)
            if inner is not None and inner not in done:
                todo.append(inner)
    return seen


def offending(modules: Iterable[str], forbidden: tuple[str, ...]) -> list[str]:
    """``module: imports X (via Y)`` for each forbidden import reachable from ``modules``."""
    problems = []
    for module in sorted(modules):
        for name, via in sorted(reachable(module).items()):
            if any(name == bad or name.startswith(bad + '.') for bad in forbidden):
                problems.append(f'{module}: imports {name} (in {via})')
    return problems


def _under(prefixes: Iterable[str]) -> list[str]:
    return [m for m in MODULES if any(m == p or m.startswith(p + '.') for p in prefixes)]


def test_imports_follow_the_package_rules() -> None:
    assert SOURCE.is_dir()
    assert violations(PACKAGE, SOURCE) == []


def test_every_device_has_one_folder() -> None:
    for device in DEVICES:
        for part in ('codec', 'device', 'config', 'module'):
            assert f'{PACKAGE}.{device}.{part}' in MODULES, f'{device}/{part}.py is missing'


def test_codecs_import_neither_rclpy_nor_wurde_core() -> None:
    codecs = [f'{PACKAGE}.{device}.codec' for device in DEVICES]
    assert offending(codecs, ROS) == []


def test_simulated_world_and_raycaster_import_no_rclpy() -> None:
    models = [m for m in _under([f'{PACKAGE}.sim']) if m not in _under(SIM_PROGRAMS)]
    assert f'{PACKAGE}.sim.world' in models and f'{PACKAGE}.sim.raycast' in models
    assert offending(models, ROS) == []


def test_real_drivers_never_import_the_simulator() -> None:
    drivers = [m for m in MODULES if m not in _under([f'{PACKAGE}.sim'])]
    assert f'{PACKAGE}.sick.module' in drivers
    assert offending(drivers, (f'{PACKAGE}.sim',)) == []


def test_relative_imports_resolve() -> None:
    """Every module parses and each import of the package names a module that exists, so the rules
    above see every edge."""
    missing = [f'{module}: {name}' for module in sorted(MODULES) for name in direct_imports(module)
               if name.startswith(PACKAGE + '.') and _resolve(name) is None]
    assert missing == []


def test_image_codec_and_the_eyes_displays_import_no_ros() -> None:
    """The encodings are pure functions over bytes; the Eye's frame store, status, window and page
    know no ROS either (only its module does)."""
    pure = [f'{PACKAGE}.image_codec'] + [f'{PACKAGE}.eye.{part}'
                                         for part in ('frames', 'status', 'window', 'web')]
    assert all(module in MODULES for module in pure)
    assert offending(pure, ROS) == []


def test_the_joystick_library_imports_neither_rclpy_nor_wurde_core() -> None:
    """The joystick has no server module of its own (BlindTeleop reads it, guide 7.9): everything
    but its two programs is pure, so any program may read a joystick."""
    pure = [f'{PACKAGE}.joystick.{part}' for part in
            ('codec', 'config', 'device', 'controller', 'emulator', 'script')]
    assert all(module in MODULES for module in pure)
    assert offending([*pure, f'{PACKAGE}.blind_teleop.drive'], ROS) == []
