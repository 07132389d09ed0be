"""Checked reading of XML elements: known children only, known attributes only, typed values.

Every reader of the suite's XML files (maps, device configs) takes an element's attributes
through :class:`Attributes` and its children through :func:`children`, so an unknown tag or
attribute is refused by name, as launch_xml does (docs/style.md), and every conversion error names the
file, the line, the element and the attribute (:class:`~wurde_idl.errors.ConfigError`).  Parse
the file first with :func:`wurde_idl.safe_xml.parse_file`.  Pure Python (lxml only).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from typing import Any

from lxml import etree

from .errors import ConfigError

__all__ = ['Attributes', 'checked_attributes', 'children', 'local_name']

_TRUE = {'true', 'yes', '1', 'on'}
_FALSE = {'false', 'no', '0', 'off'}


def local_name(node: etree._Element) -> str:
    """The tag without its namespace (WURDE files carry ``xmlns`` attributes)."""
    return etree.QName(node).localname if isinstance(node.tag, str) else ''


def children(path: str | os.PathLike[str], node: etree._Element,
             allowed: Iterable[str]) -> list[etree._Element]:
    """The element children of ``node``; any tag not in ``allowed`` is refused."""
    allowed = set(allowed)
    found = []
    for child in node:
        if not isinstance(child.tag, str):
            continue  # comments and processing instructions
        tag = local_name(child)
        if tag not in allowed:
            raise ConfigError(path, child.sourceline,
                              f'unknown element <{tag}> in <{local_name(node)}>; expected one of '
                              f'{", ".join(sorted(allowed))}')
        found.append(child)
    return found


def checked_attributes(path: str | os.PathLike[str], node: etree._Element, *, required: Iterable[str] = (),
                       optional: Iterable[str] = (), nonempty: bool = False,
                       namespaced: bool = True) -> dict[str, str]:
    """The element's attributes by name, refused with :class:`ConfigError` (file, line, reason)
    when one is not among ``required`` and ``optional`` or a required one is missing (or, with
    ``nonempty``, blank).  Namespaced attributes (``xsi:schemaLocation``) are passed over, or
    refused too when ``namespaced`` is False.  The one attribute check of every XML file a user
    writes (configs, maps, mappings, role configs, interfaces)."""
    required, optional = set(required), set(optional)
    tag = local_name(node)
    values: dict[str, str] = {}
    for key, value in node.attrib.items():
        if namespaced and etree.QName(key).namespace is not None:
            continue
        values[str(key)] = str(value)
    unknown = set(values) - required - optional
    if unknown:
        raise ConfigError(path, node.sourceline,
                          f'unknown attribute(s) {", ".join(sorted(unknown))} on <{tag}>; allowed: '
                          f'{", ".join(sorted(required | optional)) or "none"}')
    missing = {name for name in required
               if name not in values or nonempty and not values[name].strip()}
    if missing:
        raise ConfigError(path, node.sourceline, f'<{tag}> needs {"non-empty " if nonempty else ""}'
                                                 f'attribute(s) {", ".join(sorted(missing))}')
    return values


class Attributes:
    """The attributes of one element, checked against the required and optional names.

    Typed getters convert and raise :class:`ConfigError` naming the file, the line, the element and
    the attribute.
    """

    def __init__(self, path: str | os.PathLike[str], node: etree._Element, *,
                 required: Iterable[str] = (), optional: Iterable[str] = ()) -> None:
        self.path = os.fspath(path)
        self.node = node
        self.line = node.sourceline
        self.tag = local_name(node)
        self.values: dict[str, str] = dict(
            checked_attributes(path, node, required=required, optional=optional))

    def error(self, reason: str) -> ConfigError:
        return ConfigError(self.path, self.line, reason)

    def _default(self, name: str, default: Any) -> Any:
        """What an absent attribute reads as: ``default``, or an error when there is none."""
        if default is None:
            raise self.error(f'<{self.tag}> needs attribute {name}')
        return default

    def has(self, name: str) -> bool:
        return name in self.values

    def text(self, name: str, default: str | None = None) -> str:
        value = self.values.get(name)
        if value is None:
            return self._default(name, default)
        value = value.strip()
        if not value:
            raise self.error(f'attribute {name} of <{self.tag}> is empty')
        return value

    def choice(self, name: str, choices: Iterable[str], default: str | None = None) -> str:
        value = self.text(name, default)
        options = list(choices)
        if value not in options:
            raise self.error(f'attribute {name}="{value}" of <{self.tag}> must be one of '
                             f'{", ".join(options)}')
        return value

    def boolean(self, name: str, default: bool | None = None) -> bool:
        raw = self.values.get(name)
        if raw is None:
            return self._default(name, default)
        word = raw.strip().lower()
        if word in _TRUE:
            return True
        if word in _FALSE:
            return False
        raise self.error(f'attribute {name}="{raw}" of <{self.tag}> is not true or false')

    def number(self, name: str, default: float | None = None, *, minimum: float | None = None,
               maximum: float | None = None, integer: bool = False) -> Any:
        raw = self.values.get(name)
        if raw is None:
            return self._default(name, default)
        try:
            value: float = int(raw, 0) if integer else float(raw)
        except ValueError as error:
            kind = 'an integer' if integer else 'a number'
            raise self.error(f'attribute {name}="{raw}" of <{self.tag}> is not {kind}') from error
        if not math.isfinite(value):
            raise self.error(f'attribute {name}="{raw}" of <{self.tag}> is not finite')
        if minimum is not None and value < minimum:
            raise self.error(f'attribute {name}={raw} of <{self.tag}> is below {minimum}')
        if maximum is not None and value > maximum:
            raise self.error(f'attribute {name}={raw} of <{self.tag}> is above {maximum}')
        return value
