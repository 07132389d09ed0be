"""Read and validate interface definition files (seed: WURDE Programming Guide 3.3).

The reader is strict: an unknown tag, attribute or type, a bad identifier, a duplicate, an
``array_size`` naming a missing or non-integral member, a missing mandatory section: each is refused
with an :class:`~wurde_idl.errors.InterfaceError` naming the file, the line and the reason.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Sequence

from lxml import etree

from . import names, safe_xml, types
from .errors import ConfigError, InterfaceError
from .model import Interface, Member, StructType
from .xml_elements import checked_attributes

_VERSION = re.compile(r'^\d+(\.\d+)*$')
_INTERFACE_CHILDREN = ('author', 'description', 'type', 'info', 'publish')


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, node: etree._Element | None, reason: str) -> InterfaceError:
        return InterfaceError(self.path, node.sourceline if node is not None else None, reason)

    def elements(self, node: etree._Element) -> list[etree._Element]:
        """Child elements of ``node``; comments are allowed, stray text is not."""
        children = []
        if node.text and node.text.strip():
            raise self.fail(node, f'<{node.tag}> may not contain text: "{node.text.strip()[:40]}"')
        for child in node:
            if isinstance(child.tag, str):
                children.append(child)
            if child.tail and child.tail.strip():
                raise self.fail(child, f'stray text after <{child.tag if isinstance(child.tag, str) else "!--"}>: '
                                f'"{child.tail.strip()[:40]}"')
        return children

    def attributes(self, node: etree._Element, required: Sequence[str],
                   optional: Sequence[str] = ()) -> dict[str, str]:
        try:
            values = checked_attributes(self.path, node, required=required, optional=optional, nonempty=True,
                                        namespaced=False)
        except ConfigError as error:
            raise self.fail(node, error.reason) from None
        return {key: value.strip() for key, value in values.items()}

    def text_only(self, node: etree._Element) -> str:
        self.attributes(node, ())
        for child in node:
            if isinstance(child.tag, str):
                raise self.fail(child, f'<{node.tag}> holds text only, not <{child.tag}>')
        text = ''.join(node.itertext()).strip()
        if not text:
            raise self.fail(node, f'<{node.tag}> is empty')
        return text

    def read(self, root: etree._Element) -> Interface:
        attrs = self.attributes(root, ('name', 'version'))
        name, version = attrs['name'], attrs['version']
        why = names.check_type_name(name)
        if why:
            raise self.fail(root, f'interface name "{name}" {why}')
        if not _VERSION.match(version):
            raise self.fail(root, f'interface version "{version}" must look like 1.0')
        sections: dict[str, list[etree._Element]] = {tag: [] for tag in _INTERFACE_CHILDREN}
        for child in self.elements(root):
            if child.tag not in sections:
                raise self.fail(child, f'unknown tag <{child.tag}> in <interface> (allowed: '
                                f'{", ".join(_INTERFACE_CHILDREN)})')
            sections[child.tag].append(child)
        for tag in ('author', 'description'):
            if not sections[tag]:
                raise self.fail(root, f'interface "{name}" has no <{tag}> section (mandatory)')
        for tag in ('author', 'description', 'info', 'publish'):
            if len(sections[tag]) > 1:
                raise self.fail(sections[tag][1], f'a second <{tag}> section (only one is allowed)')
        author = self.text_only(sections['author'][0])
        description = self.text_only(sections['description'][0])

        type_nodes: dict[str, etree._Element] = {}
        for node in sections['type']:
            type_name = self.attributes(node, ('name',))['name']
            why = names.check_type_name(type_name)
            if why:
                raise self.fail(node, f'type name "{type_name}" {why}')
            if type_name in types.BUILTIN_TYPE_NAMES or type_name in types.SUPPORT_MESSAGES:
                raise self.fail(node, f'type name "{type_name}" is a built-in type')
            if type_name in (name, f'{name}Data', f'{name}Info'):
                raise self.fail(node, f'type name "{type_name}" clashes with the messages of '
                                f'interface "{name}"')
            if type_name in type_nodes:
                raise self.fail(node, f'type "{type_name}" is defined twice (first on line '
                                f'{type_nodes[type_name].sourceline})')
            type_nodes[type_name] = node

        dropped: dict[str, tuple[str, ...]] = {}
        struct_types = []
        for type_name, node in type_nodes.items():
            members, gone = self.section(node, set(type_nodes))
            dropped[type_name] = gone
            struct_types.append(StructType(type_name, members, node.sourceline or 0))
        self.check_cycles(struct_types, type_nodes)

        info = publish = None
        if sections['info']:
            info, dropped['info'] = self.section(sections['info'][0], set(type_nodes))
        if sections['publish']:
            publish, dropped['publish'] = self.section(sections['publish'][0], set(type_nodes))
        return Interface(name=name, version=version, author=author, description=description,
                         types=tuple(struct_types), info=info, publish=publish, path=self.path,
                         line=root.sourceline or 0, dropped=dropped)

    def section(self, node: etree._Element, local_types: set[str]
                ) -> tuple[tuple[Member, ...], tuple[str, ...]]:
        """Read the ``<data>`` members of a type, info or publish section."""
        if node.tag != 'type':
            self.attributes(node, ())
        raw: list[tuple[etree._Element, dict[str, str]]] = []
        seen: dict[str, etree._Element] = {}
        ros_seen: dict[str, str] = {}
        for child in self.elements(node):
            if child.tag != 'data':
                raise self.fail(child, f'unknown tag <{child.tag}> in <{node.tag}> (only <data>)')
            attrs = self.attributes(child, ('name', 'type'), ('array_size',))
            member = attrs['name']
            why = names.check_member_name(member)
            if why:
                raise self.fail(child, f'member name "{member}" {why}')
            if member in seen:
                raise self.fail(child, f'member "{member}" is defined twice in <{node.tag}> '
                                f'(first on line {seen[member].sourceline})')
            ros = names.field_name(member)
            if ros in ros_seen:
                raise self.fail(child, f'member "{member}" and "{ros_seen[ros]}" both become ROS '
                                f'field "{ros}"')
            type_name = types.canonical(attrs['type'])
            if type_name not in types.BUILTIN_TYPE_NAMES and type_name not in local_types:
                raise self.fail(child, f'unknown type "{attrs["type"]}" for member "{member}" '
                                '(not a WURDE type nor a <type> of this file)')
            seen[member] = child
            ros_seen[ros] = member
            raw.append((child, {**attrs, 'type': type_name}))

        counts = {attrs['array_size'] for _, attrs in raw if 'array_size' in attrs}
        for child, attrs in raw:
            count = attrs.get('array_size')
            if count is None:
                continue
            if count not in seen:
                raise self.fail(child, f'array_size "{count}" of member "{attrs["name"]}" names '
                                f'no member of <{node.tag}>')
            count_attrs = dict(seen[count].attrib)
            count_type = types.SCALARS.get(types.canonical(count_attrs['type']))
            if count_type is None or not count_type.integral:
                raise self.fail(child, f'array_size "{count}" of member "{attrs["name"]}" must '
                                f'name an integer member (Byte, Integer, Long), not '
                                f'{count_attrs["type"]}')
            if 'array_size' in count_attrs:
                raise self.fail(child, f'array_size "{count}" names an array member')
        members = tuple(
            Member(name=names.field_name(attrs['name']), xml_name=attrs['name'], type=attrs['type'],
                   is_array='array_size' in attrs, count_member=attrs.get('array_size'),
                   line=child.sourceline or 0)
            for child, attrs in raw if attrs['name'] not in counts)
        return members, tuple(sorted(counts))

    def check_cycles(self, struct_types: Iterable[StructType],
                     type_nodes: dict[str, etree._Element]) -> None:
        uses = {t.name: {m.type for m in t.members if m.type in type_nodes} for t in struct_types}
        state: dict[str, int] = {}

        def visit(type_name: str, trail: list[str]) -> None:
            if state.get(type_name) == 2:
                return
            if state.get(type_name) == 1:
                cycle = ' -> '.join(trail[trail.index(type_name):] + [type_name])
                raise self.fail(type_nodes[type_name], f'types refer to each other in a cycle: {cycle}')
            state[type_name] = 1
            for used in sorted(uses[type_name]):
                visit(used, trail + [type_name])
            state[type_name] = 2

        for type_name in uses:
            visit(type_name, [])


def read_interface(path: str | os.PathLike[str]) -> Interface:
    """Read and validate one interface file.

    :param path: the ``.xml`` file (its root must be ``<interface>``).
    :raises InterfaceError: naming the file, the line and the reason when it is refused.
    """
    path = os.fspath(path)
    root = safe_xml.parse_file(path, root_tag='interface', error=InterfaceError)
    return _Reader(path).read(root)


def read_interfaces(paths: Iterable[str | os.PathLike[str]],
                    known: dict[str, str] | None = None) -> list[Interface]:
    """Read several files that form one package; refuse duplicate interface and type names.

    :param paths: the interface files, read in this order.
    :param known: message names already taken (by installed packages, say), mapped to where they
        are, for the error; None: none.
    :raises InterfaceError: for the first file refused.
    """
    taken: dict[str, str] = dict(known or {})
    result = []
    for path in paths:
        interface = read_interface(path)
        generated = [(interface.name, interface.line), (interface.data_message, interface.line),
                     (interface.info_message, interface.line)]
        generated += [(t.name, t.line) for t in interface.types]
        for message, line in generated:
            if message in taken:
                raise InterfaceError(interface.path, line, f'"{message}" is already defined by '
                                     f'{taken[message]} (names must be unique; never reuse an '
                                     'interface name, even with another version)')
        for message, line in generated:
            taken[message] = f'{interface.path}:{line}'
        result.append(interface)
    return result
