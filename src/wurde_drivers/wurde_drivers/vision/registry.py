"""Finding camera and operator classes by the names the configs use.

Cameras: the config's ``type`` (``firewire``, ``playback``, ``sim``) names a class imported only
when used (the ``sim`` camera lives with the simulator's dummies: a real module that never opens
one never imports the simulator).

Operators: the ``type`` of an ``<operator>`` is looked up, in order, among the classes of the
vision config's ``<plugin path>`` modules (a dotted module or a ``.py`` file: every
:class:`~wurde_drivers.vision.operator.Operator` subclass it defines, by class name), then the
entry points of group ``wurde.vision_operators`` (how a package ships operators: the shipped
ImageWriter, ImagePublisher and StereoDataCollector are registered that way in setup.py). A
WURDE C++ plugin library (``.so``) is skipped with a notice (guide 7.2.2's plugins; their operators
are built in). A ``.py`` plugin runs with the module's rights, so one that others than its owner
may write is refused.
"""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import os
import stat
import sys
from collections.abc import Callable, Iterable
from importlib.metadata import entry_points
from types import ModuleType

from wurde_idl.errors import ConfigError

from .camera import Camera
from .operator import Operator
from .vision_config import OperatorSpec, PluginSpec

__all__ = ['CAMERA_CLASSES', 'ENTRY_POINT_GROUP', 'camera_class', 'load_plugins', 'operator_class']

ENTRY_POINT_GROUP = 'wurde.vision_operators'
#: Camera type -> ``module:Class``.
CAMERA_CLASSES = {
    'firewire': 'wurde_drivers.vision.capture:CaptureCamera',
    'playback': 'wurde_drivers.vision.playback:PlaybackCamera',
    'sim': 'wurde_drivers.sim.dummies.camera:SimCamera',
}
#: The shipped operators, for when the package's entry points are not installed (a source tree).
_SHIPPED = {
    'ImageWriter': 'wurde_drivers.vision.operators.image_writer:ImageWriter',
    'ImagePublisher': 'wurde_drivers.vision.operators.image_publisher:ImagePublisher',
    'StereoDataCollector': 'wurde_drivers.vision.operators.stereo_collector:StereoDataCollector',
}


def _load(target: str) -> type:
    module, _, name = target.partition(':')
    return getattr(importlib.import_module(module), name)


def camera_class(type_name: str) -> type[Camera]:
    """The class of camera type ``type_name``. :raises KeyError: an unknown type."""
    return _load(CAMERA_CLASSES[type_name])


def _check_owner_only(plugin: PluginSpec) -> None:
    """Refuse a plugin file that others than its owner may write: loading it runs its code."""
    try:
        mode = os.stat(plugin.path).st_mode
    except OSError as error:
        raise ConfigError(plugin.file, plugin.line, f'plugin {plugin.path}: {error.strerror}') from error
    if mode & (stat.S_IWGRP | stat.S_IWOTH):
        raise ConfigError(plugin.file, plugin.line,
                          f'plugin {plugin.path} is writable by others than its owner '
                          f'(mode {stat.filemode(mode)}); loading it would run their code: chmod go-w')


def _import(plugin: PluginSpec) -> ModuleType:
    if plugin.path.endswith('.py'):
        _check_owner_only(plugin)
        name = f'wurde_vision_plugin_{abs(hash(plugin.path))}'
        spec = importlib.util.spec_from_file_location(name, plugin.path)
        if spec is None or spec.loader is None:
            raise ImportError(f'cannot load {plugin.path}')
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module
    return importlib.import_module(plugin.path)


def load_plugins(plugins: Iterable[PluginSpec], report: Callable[[str], object]) -> dict[str, type[Operator]]:
    """Import the plugins; their operator classes by class name.

    :raises ConfigError: a plugin that cannot be imported (with its ``<plugin>``'s line; the
        import error chained).
    """
    found: dict[str, type[Operator]] = {}
    for plugin in plugins:
        if plugin.path.endswith('.so'):
            report(f'plugin {plugin.path}: a WURDE C++ library; not loaded (ImageWriter, '
                   'ImagePublisher and StereoDataCollector are built in)')
            continue
        try:
            module = _import(plugin)
        except ConfigError:
            raise
        except Exception as error:  # an import runs arbitrary code: report whatever it raises
            raise ConfigError(plugin.file, plugin.line,
                              f'plugin {plugin.path} cannot be imported: {error!r}') from error
        for name, value in vars(module).items():
            if inspect.isclass(value) and issubclass(value, Operator) and value is not Operator:
                found[name] = value
    return found


def operator_class(spec: OperatorSpec, plugins: dict[str, type[Operator]]) -> type[Operator]:
    """The class for ``spec.type``. :raises ConfigError: no plugin or entry point has it."""
    if spec.type in plugins:
        return plugins[spec.type]
    points = {point.name: point for point in entry_points(group=ENTRY_POINT_GROUP)}
    try:
        if spec.type in points:
            value = points[spec.type].load()
        elif spec.type in _SHIPPED:
            value = _load(_SHIPPED[spec.type])
        else:
            known = sorted({*plugins, *points, *_SHIPPED})
            raise spec.error(f'unknown operator type "{spec.type}" (known: {", ".join(known)})')
    except ImportError as error:
        raise spec.error(f'operator type "{spec.type}" cannot be imported: {error}') from error
    if not (inspect.isclass(value) and issubclass(value, Operator)):
        raise spec.error(f'entry point "{spec.type}" is not an Operator class')
    return value
