"""MCP configuration and mappings (seed: WURDE Programming Guide 1.1.5, 6.1, 6.2, appendix 10.1.1).

Both seed forms of the MCP configuration are read:

- chapter 1's ``<mcp-config><module name="..."><binary>b</binary><options>-n X</options></module>``;
- the appendix's ``<module name="..." binary="b">`` with ``<arg value="..."/>`` and
  ``<connect consumer="..." supplier="..." interface="..."/>`` children, alone or inside the
  combined ``<robot>`` file (its ``<wurde-config>`` is RoleConfiguration's business).

Per module, optional attributes ``locale`` (internal | external) and ``managed`` (managed |
unmanaged | critical) set the guide's locale and managed state (6.1).  A module with no binary and
no explicit locale is external (the MCP watches it but cannot start it, like the appendix's
BlindTeleop); an internal module must name its binary.  The mapping file is
``<mcp-mappings><connect module="M"><input interface="I" source="S" object="O"/>``; a module
named only there is external, with a warning naming file and line (chapter 1's files, as
printed, map BlindTeleop without listing it).  Everything else — unknown tags or attributes,
unknown interfaces in mappings, one stream mapped as two interfaces, hostile XML — is refused
with file, line and reason before anything starts.

Ours (issue 39): ``<container name="C" [scheduling="cooperative" [quantum="S"]]>`` holds internal
``<module>`` elements run in one process (:mod:`wurde_mcp.container`), a thread each or taking
turns in one (:mod:`wurde_core.cooperative`); their binary is ``package/executable`` (a Python
console script) or ``python.module:function``; a container's name is not a module's.
"""

from __future__ import annotations

import math
import os
import re
import shlex
from collections.abc import Iterable, Set
from dataclasses import dataclass, field
from enum import Enum
from typing import TypeVar

from lxml import etree

from wurde_core import ConfigError, ProcessLocale, ProcessType
from wurde_core.cooperative import QUANTUM_S
from wurde_idl.safe_xml import parse_file
from wurde_idl.xml_elements import checked_attributes


#: A contained module's binary: ``package/executable`` or ``python.module:function``.
#: A container's ``scheduling``: a thread per module (the default), or turns in one thread.
SCHEDULING = ('threads', 'cooperative')
#: The longest quantum of a cooperative container (s): a module sleeps at most this much longer.
MAX_QUANTUM_S = 0.1
CONTAINED_BINARY = re.compile(r'[\w-]+/[\w.-]+|[\w.]+:\w+')


@dataclass(frozen=True)
class Mapping:
    """One consumer-to-stream mapping: the consumer ``object`` of ``interface`` in ``module``
    is connected to stream ``source``."""

    module: str
    interface: str
    source: str
    object: str
    path: str = ''
    line: int = 0


@dataclass
class ModuleSpec:
    """A module the MCP knows."""

    name: str
    binary: str = ''
    args: list[str] = field(default_factory=list)
    locale: ProcessLocale = ProcessLocale.INTERNAL
    managed: ProcessType = ProcessType.MANAGED
    path: str = ''
    line: int = 0
    #: The ``<container>`` the module runs in (empty: a process of its own).
    container: str = ''


@dataclass
class McpConfig:
    """Modules by name and mappings by module."""

    modules: dict[str, ModuleSpec] = field(default_factory=dict)
    mappings: list[Mapping] = field(default_factory=list)
    #: Containers by name: where each was declared (``file:line``).
    containers: dict[str, str] = field(default_factory=dict)
    #: The containers whose modules take turns in one thread (``scheduling="cooperative"``), each
    #: with its hub's quantum in seconds (``quantum``, :data:`wurde_core.cooperative.QUANTUM_S`).
    cooperative: dict[str, float] = field(default_factory=dict)
    #: Warnings from :func:`validate`, each starting with ``file:line:``.
    warnings: list[str] = field(default_factory=list)

    def mappings_for(self, module: str) -> list[Mapping]:
        """The mappings of one module, in the order they were read.

        :param module: the module's name, as the configuration or the mappings name it.
        """
        return [m for m in self.mappings if m.module == module]


_E = TypeVar('_E', bound=Enum)


def _local(tag: object) -> str | None:
    return etree.QName(tag).localname if isinstance(tag, str) else None


def _elements(path: str, node: etree._Element) -> Iterable[etree._Element]:
    for child in node:
        tag = _local(child.tag)
        if tag is None or tag == 'comment':
            continue
        yield child


def _attributes(path: str, node: etree._Element, allowed: set[str],
                required: Set[str] = frozenset()) -> dict[str, str]:
    """``node``'s attributes, stripped; required ones must not be blank."""
    values = checked_attributes(path, node, required=required, optional=allowed, nonempty=True)
    return {attr: value.strip() for attr, value in values.items()}


def _enum(path: str, node: etree._Element, attr: str, value: str, enum: type[_E]) -> _E:
    try:
        return enum[value.upper()]
    except KeyError:
        allowed = ', '.join(e.name.lower() for e in enum)
        raise ConfigError(path, node.sourceline,
                          f'{attr}="{value}" is not one of {allowed}') from None


def _text(path: str, node: etree._Element) -> str:
    _attributes(path, node, set())
    for child in _elements(path, node):
        raise ConfigError(path, child.sourceline, f'<{_local(node.tag)}> holds text only')
    return (node.text or '').strip()


def _split(path: str, node: etree._Element, text: str) -> list[str]:
    try:
        return shlex.split(text)
    except ValueError as exc:
        raise ConfigError(path, node.sourceline, f'cannot split arguments {text!r}: {exc}') from exc


def read_mcp_config(path: str | os.PathLike[str], config: McpConfig | None = None) -> McpConfig:
    """Read an MCP configuration file (either seed form).

    :param path: the file: an ``<mcp-config>``, or a ``<robot>`` file holding exactly one.
    :param config: the configuration to add the modules and their ``<connect>`` mappings to
        (None: a new one); a module it already has is refused as defined twice.
    :returns: ``config``, or the new configuration.
    :raises ConfigError: naming the file, the line and the reason.
    """
    path = os.fspath(path)
    config = config or McpConfig()
    root = parse_file(path, root_tag=('mcp-config', 'robot'))
    if _local(root.tag) == 'robot':
        found = [c for c in _elements(path, root) if _local(c.tag) == 'mcp-config']
        for child in _elements(path, root):
            if _local(child.tag) not in ('mcp-config', 'wurde-config'):
                raise ConfigError(path, child.sourceline,
                                  f'unknown tag <{_local(child.tag)}> in <robot>')
        if len(found) != 1:
            raise ConfigError(path, root.sourceline,
                              f'<robot> must hold exactly one <mcp-config>, found {len(found)}')
        root = found[0]
    _attributes(path, root, set())
    for node in _elements(path, root):
        if _local(node.tag) == 'container':
            _read_container(path, node, config)
            continue
        if _local(node.tag) != 'module':
            raise ConfigError(path, node.sourceline, f'unknown tag <{_local(node.tag)}> in <mcp-config> '
                              '(only <module> and <container>)')
        _read_module(path, node, config)
    for name, where in config.containers.items():
        if name in config.modules:
            raise ConfigError(path, int(where.rsplit(':', 1)[1]), f'container "{name}" has the name of '
                              'a module')
    return config


def _read_container(path: str, node: etree._Element, config: McpConfig) -> None:
    """``<container name="C" [scheduling="threads|cooperative"]>`` and its ``<module>`` elements,
    each a module of container C."""
    attrs = _attributes(path, node, {'name', 'scheduling', 'quantum'}, {'name'})
    name = attrs['name']
    scheduling = attrs.get('scheduling', 'threads')
    if scheduling not in SCHEDULING:
        raise ConfigError(path, node.sourceline, f'container "{name}": scheduling "{scheduling}" is '
                          f'not one of {", ".join(SCHEDULING)}')
    if scheduling == 'cooperative':
        config.cooperative[name] = _quantum(path, node, attrs.get('quantum'))
    elif 'quantum' in attrs:
        raise ConfigError(path, node.sourceline, f'container "{name}": a quantum is only for '
                          'scheduling="cooperative"')
    if name in config.containers:
        raise ConfigError(path, node.sourceline, f'container "{name}" is defined twice (first at '
                          f'{config.containers[name]})')
    config.containers[name] = f'{path}:{node.sourceline or 0}'
    members = list(_elements(path, node))
    if not members:
        raise ConfigError(path, node.sourceline, f'container "{name}" holds no <module>')
    for child in members:
        if _local(child.tag) != 'module':
            raise ConfigError(path, child.sourceline,
                              f'unknown tag <{_local(child.tag)}> in <container> (only <module>)')
        _read_module(path, child, config)
        spec = config.modules[child.get('name')]
        if spec.locale != ProcessLocale.INTERNAL or not CONTAINED_BINARY.fullmatch(spec.binary):
            raise ConfigError(path, child.sourceline, f'module "{spec.name}" of container "{name}" '
                              'must be internal, its binary "package/executable" (a Python program) '
                              'or "python.module:function"')
        spec.container = name


def _quantum(path: str, node: etree._Element, text: str | None) -> float:
    """A cooperative container's ``quantum`` (seconds, 0 to :data:`MAX_QUANTUM_S`)."""
    if text is None:
        return QUANTUM_S
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 <= value <= MAX_QUANTUM_S:
        raise ConfigError(path, node.sourceline, f'quantum="{text}" is not a number of seconds '
                          f'from 0 to {MAX_QUANTUM_S}')
    return value


def _read_module(path: str, node: etree._Element, config: McpConfig) -> None:
    attrs = _attributes(path, node, {'name', 'binary', 'locale', 'managed'}, {'name'})
    name = attrs['name']
    if name in config.modules:
        first = config.modules[name]
        raise ConfigError(path, node.sourceline, f'module "{name}" is defined twice (first at '
                          f'{first.path}:{first.line})')
    spec = ModuleSpec(name=name, binary=attrs.get('binary', ''), path=path,
                      line=node.sourceline or 0)
    explicit_locale = 'locale' in attrs
    if explicit_locale:
        spec.locale = _enum(path, node, 'locale', attrs['locale'], ProcessLocale)
    if 'managed' in attrs:
        spec.managed = _enum(path, node, 'managed', attrs['managed'], ProcessType)
    for child in _elements(path, node):
        tag = _local(child.tag)
        if tag == 'binary':
            if spec.binary:
                raise ConfigError(path, child.sourceline, f'module "{name}" names its binary twice')
            spec.binary = _text(path, child)
        elif tag == 'options':
            spec.args += _split(path, child, _text(path, child))
        elif tag == 'arg':
            spec.args += _split(path, child, _attributes(path, child, {'value'}, {'value'})['value'])
        elif tag == 'connect':
            c = _attributes(path, child, {'consumer', 'supplier', 'interface'},
                            {'consumer', 'supplier', 'interface'})
            config.mappings.append(Mapping(name, c['interface'], c['supplier'], c['consumer'],
                                           path, child.sourceline or 0))
        else:
            raise ConfigError(path, child.sourceline, f'unknown tag <{tag}> in <module>')
    if not spec.binary:
        if explicit_locale and spec.locale == ProcessLocale.INTERNAL:
            raise ConfigError(path, node.sourceline,
                              f'internal module "{name}" has no binary (give <binary> or binary=)')
        spec.locale = ProcessLocale.EXTERNAL
    config.modules[name] = spec


def read_mcp_mappings(path: str | os.PathLike[str], config: McpConfig) -> McpConfig:
    """Read a mappings file into ``config``.

    :param path: the ``<mcp-mappings>`` file.
    :param config: the configuration whose mappings it adds to; the modules they name are not
        checked here (:func:`validate` does).
    :returns: ``config``.
    :raises ConfigError: naming the file, the line and the reason.
    """
    path = os.fspath(path)
    root = parse_file(path, root_tag='mcp-mappings')
    _attributes(path, root, set())
    for node in _elements(path, root):
        if _local(node.tag) != 'connect':
            raise ConfigError(path, node.sourceline,
                              f'unknown tag <{_local(node.tag)}> in <mcp-mappings>')
        module = _attributes(path, node, {'module'}, {'module'})['module']
        for child in _elements(path, node):
            if _local(child.tag) != 'input':
                raise ConfigError(path, child.sourceline,
                                  f'unknown tag <{_local(child.tag)}> in <connect>')
            a = _attributes(path, child, {'interface', 'source', 'object'}, {'interface', 'source'})
            config.mappings.append(Mapping(module, a['interface'], a['source'], a.get('object', ''),
                                           path, child.sourceline or 0))
    return config


def validate(config: McpConfig, interfaces: Iterable[str]) -> list[str]:
    """Check the mappings against the modules and the installed interfaces; return warnings.

    A module that only the mappings name (the guide's chapter 1 maps BlindTeleop, a program the
    user starts by hand, without listing it in mcp-config) becomes an external module: the MCP
    watches it and answers its requests but cannot start it, and a warning names the mapping's
    file and line.  Refused with file and line: a mapping naming an unknown interface, and two
    mappings that use one stream as two different interfaces (:func:`static_conflict`).

    :param config: the configuration read; a module only the mappings name is added to its
        modules as external, and the warnings are appended to its ``warnings``.
    :param interfaces: the names of the installed interfaces.
    :returns: the warnings of this call, each starting with ``file:line:``.
    :raises ConfigError: naming the file, the line and the reason.
    """
    known = set(interfaces)
    warnings = []
    for mapping in config.mappings:
        if mapping.interface not in known:
            raise ConfigError(mapping.path, mapping.line,
                              f'mapping names unknown interface "{mapping.interface}"')
        if mapping.module not in config.modules:
            config.modules[mapping.module] = ModuleSpec(
                name=mapping.module, locale=ProcessLocale.EXTERNAL, path=mapping.path,
                line=mapping.line)
            warnings.append(f'{mapping.path}:{mapping.line}: module "{mapping.module}" is named '
                            'only in the mappings, not in the MCP configuration: watched as an '
                            'external module (the MCP cannot start it)')
    conflict = static_conflict(config.mappings)
    if conflict is not None:
        mapping, reason = conflict
        raise ConfigError(mapping.path, mapping.line, reason)
    config.warnings.extend(warnings)
    return warnings


def where(mapping: Mapping) -> str:
    """``file:line`` of a mapping.

    :param mapping: a mapping as read from its file.
    """
    return f'{mapping.path}:{mapping.line}'


def static_conflict(mappings: Iterable[Mapping]) -> tuple[Mapping, str] | None:
    """The first mapping that uses a stream as another interface than an earlier mapping does,
    with the reason; ``None`` when they agree.

    :param mappings: the mappings in the order they were read (the earlier one is kept as right).
    """
    first: dict[str, Mapping] = {}
    for mapping in mappings:
        earlier = first.setdefault(mapping.source, mapping)
        if earlier.interface != mapping.interface:
            return mapping, (f'mapping connects {mapping.interface} object '
                             f'"{mapping.object or "*"}" of module "{mapping.module}" to stream '
                             f'"{mapping.source}", which the mapping at {where(earlier)} uses as '
                             f'{earlier.interface}')
    return None
