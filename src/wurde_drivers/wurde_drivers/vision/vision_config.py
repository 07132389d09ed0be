"""Reader of ``vision-config.xml``, the VisionModule's layout file (WURDE guide 7.2.2).

One or more ``<module name>`` (a VisionModule started with ``-n NAME`` uses the one of that
name), each with an optional ``<comment>``, its ``<camera name>`` elements and its
``<operator name type>`` elements; an operator names its one or two cameras in a ``camera``
attribute or ``<camera name>`` children, and its options in ``<option name value>`` children.
``<plugin path>`` says where more operator classes come from: a dotted Python module or a ``.py``
file (relative: from this file's directory); a WURDE C++ library (``.so``, as the appendix lists)
is accepted and skipped with a notice, its operators being built in (:mod:`.registry`).

docs/vision.md ("Vision") describes the file and docs/wurde-drivers.md ("vision.vision_config") shows
an example; config/vision/vision-config.xml is the guide appendix's, read by a test as shipped.
Operator types are checked when the module loads them (:mod:`.registry`), with this file's line.
Pure Python (lxml).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping

from lxml import etree
from wurde_idl.errors import ConfigError

from ..xml_config import Attributes, children, read_root

__all__ = ['ModuleLayout', 'OperatorSpec', 'PluginSpec', 'VisionConfig', 'load_vision_config']

ROOT_TAG = 'vision-config'


@dataclasses.dataclass(frozen=True)
class OperatorSpec:
    """One ``<operator>``: instance name, type, its cameras (first is "main") and options."""

    name: str
    type: str
    cameras: tuple[str, ...]
    options: Mapping[str, str]
    path: str = ''
    line: int | None = None

    def error(self, reason: str) -> ConfigError:
        return ConfigError(self.path, self.line, f'operator "{self.name}": {reason}')


@dataclasses.dataclass(frozen=True)
class ModuleLayout:
    """One ``<module>``: the cameras it opens and the operators it runs."""

    name: str
    cameras: tuple[str, ...]
    operators: tuple[OperatorSpec, ...]
    comment: str = ''
    path: str = ''
    line: int | None = None


@dataclasses.dataclass(frozen=True)
class PluginSpec:
    """One ``<plugin path>``, with the path resolved (a dotted module stays as it is)."""

    path: str
    file: str = ''
    line: int | None = None


@dataclasses.dataclass(frozen=True)
class VisionConfig:
    path: str
    modules: Mapping[str, ModuleLayout]
    plugins: tuple[PluginSpec, ...]

    def module(self, name: str) -> ModuleLayout:
        """The layout a module named ``name`` uses (guide 7.2.2: chosen by ``-n``).

        :raises ConfigError: no ``<module>`` of that name; names the ones there are.
        """
        if name not in self.modules:
            raise ConfigError(self.path, None, f'no <module name="{name}"> (modules: '
                                               f'{", ".join(self.modules)}); use -n')
        return self.modules[name]


def _named(path: str, node: etree._Element) -> tuple[str, int | None]:
    attrs = Attributes(path, node, required=('name',))
    return attrs.text('name'), attrs.line


def _operator(path: str, node: etree._Element, module_cameras: tuple[str, ...]) -> OperatorSpec:
    attrs = Attributes(path, node, required=('name', 'type'), optional=('camera',))
    name = attrs.text('name')
    cameras = [attrs.text('camera')] if attrs.has('camera') else []
    options: dict[str, str] = {}
    for child in children(path, node, ('camera', 'option')):
        if child.tag == 'camera':
            cameras.append(_named(path, child)[0])
            continue
        option = Attributes(path, child, required=('name', 'value'))
        key = option.text('name')
        if key in options:
            raise option.error(f'option "{key}" of operator "{name}" given twice')
        options[key] = option.values['value']
    if not 1 <= len(cameras) <= 2:
        raise attrs.error(f'operator "{name}" needs one or two cameras, has {len(cameras)}')
    for camera in cameras:
        if camera not in module_cameras:
            raise attrs.error(f'operator "{name}" uses camera "{camera}", which its module does not '
                              f'open (cameras: {", ".join(module_cameras)})')
    if len(set(cameras)) != len(cameras):
        raise attrs.error(f'operator "{name}" names camera "{cameras[0]}" twice')
    return OperatorSpec(name, attrs.text('type'), tuple(cameras), options, path, attrs.line)


def _module(path: str, node: etree._Element) -> ModuleLayout:
    name, line = _named(path, node)
    cameras: list[str] = []
    operators: list[OperatorSpec] = []
    comment = ''
    nodes = children(path, node, ('comment', 'camera', 'operator'))
    for child in nodes:
        if child.tag == 'comment':
            Attributes(path, child)
            comment = (child.text or '').strip()
        elif child.tag == 'camera':
            camera, camera_line = _named(path, child)
            if camera in cameras:
                raise ConfigError(path, camera_line, f'module "{name}" opens camera "{camera}" twice')
            cameras.append(camera)
    for child in nodes:
        if child.tag == 'operator':
            operator = _operator(path, child, tuple(cameras))
            if any(o.name == operator.name for o in operators):
                raise ConfigError(path, operator.line, f'duplicate operator name "{operator.name}" '
                                                       f'in module "{name}"')
            operators.append(operator)
    if not cameras or not operators:
        raise ConfigError(path, line, f'module "{name}" needs at least one <camera> and one <operator>')
    return ModuleLayout(name, tuple(cameras), tuple(operators), comment, path, line)


def _plugin(path: str, node: etree._Element) -> PluginSpec:
    attrs = Attributes(path, node, required=('path',))
    value = attrs.text('path')
    if '/' in value or value.endswith(('.py', '.so')):
        if not os.path.isabs(value):
            value = os.path.join(os.path.dirname(os.path.abspath(path)), value)
    return PluginSpec(value, path, attrs.line)


def load_vision_config(path: str | os.PathLike[str]) -> VisionConfig:
    """Every module layout and plugin of the file.

    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a module without cameras or operators, an operator with no camera, more than
        two, or one its module does not open, duplicate names, no module at all.
    """
    path = os.fspath(path)
    root = read_root(path, ROOT_TAG)
    modules: dict[str, ModuleLayout] = {}
    plugins: list[PluginSpec] = []
    for node in children(path, root, ('module', 'plugin')):
        if node.tag == 'plugin':
            plugins.append(_plugin(path, node))
            continue
        module = _module(path, node)
        if module.name in modules:
            raise ConfigError(path, module.line, f'duplicate module name "{module.name}" '
                                                 f'(first on line {modules[module.name].line})')
        modules[module.name] = module
    if not modules:
        raise ConfigError(path, root.sourceline, f'<{ROOT_TAG}> holds no <module>')
    return VisionConfig(path, modules, tuple(plugins))
