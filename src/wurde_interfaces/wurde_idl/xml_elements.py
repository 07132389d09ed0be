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
    """The tag without its namespace (WURDE files carry ``xmlns`` attributes).

    :param node: an lxml node; ``''`` for a comment or processing instruction.
    """
    return etree.QName(node).localname if isinstance(node.tag, str) else ''


def children(path: str | os.PathLike[str], node: etree._Element,
             allowed: Iterable[str]) -> list[etree._Element]:
    """The element children of ``node`` (comments and processing instructions passed over).

    :param path: the file, for the error.
    :param node: the parent element.
    :param allowed: the local names its children may have.
    :raises ConfigError: for the first child of another name (file, line, the names allowed).
    """
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
    writes (configs, maps, mappings, role configs, interfaces).

    :param path: the file, for the error.
    :param node: the element.
    :param required: names that must be there.
    :param optional: names that may be there.
    :param nonempty: a required attribute must also hold more than blanks.
    :param namespaced: pass over namespaced attributes (True) or refuse them (False).
    :returns: the attributes by name (the namespaced ones left out).
    """
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
        """Check the element's attributes (:func:`checked_attributes`) and keep them.

        :param path: the file, for errors.
        :param node: the element.
        :param required: names that must be there.
        :param optional: names that may be there.
        :raises ConfigError: for an unknown or a missing attribute.
        """
        self.path = os.fspath(path)
        self.node = node
        self.line = node.sourceline
        self.tag = local_name(node)
        self.values: dict[str, str] = dict(
            checked_attributes(path, node, required=required, optional=optional))

    def error(self, reason: str) -> ConfigError:
        """A ConfigError at this element's file and line, to raise.

        :param reason: what is wrong.
        """
        return ConfigError(self.path, self.line, reason)

    def _default(self, name: str, default: Any) -> Any:
        """What an absent attribute reads as: ``default``, or an error when there is none."""
        if default is None:
            raise self.error(f'<{self.tag}> needs attribute {name}')
        return default

    def has(self, name: str) -> bool:
        """Whether the element has the attribute.

        :param name: the attribute's name.
        """
        return name in self.values

    def text(self, name: str, default: str | None = None) -> str:
        """The attribute's text, stripped.

        :param name: the attribute's name.
        :param default: the value when it is absent; None: it must be there.
        :raises ConfigError: when it is absent without a default, or blank.
        """
        value = self.values.get(name)
        if value is None:
            return self._default(name, default)
        value = value.strip()
        if not value:
            raise self.error(f'attribute {name} of <{self.tag}> is empty')
        return value

    def choice(self, name: str, choices: Iterable[str], default: str | None = None) -> str:
        """The attribute's text, which must be one of ``choices``.

        :param name: the attribute's name.
        :param choices: the values allowed (the error lists them in this order).
        :param default: the value when it is absent; None: it must be there.
        :raises ConfigError: for another value, or as :meth:`text`.
        """
        value = self.text(name, default)
        options = list(choices)
        if value not in options:
            raise self.error(f'attribute {name}="{value}" of <{self.tag}> must be one of '
                             f'{", ".join(options)}')
        return value

    def boolean(self, name: str, default: bool | None = None) -> bool:
        """The attribute as a bool: true/yes/1/on or false/no/0/off, in any case.

        :param name: the attribute's name.
        :param default: the value when it is absent; None: it must be there.
        :raises ConfigError: for another word, or when it is absent without a default.
        """
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
        """The attribute as a finite number.

        :param name: the attribute's name.
        :param default: the value when it is absent (returned unchecked); None: it must be there.
        :param minimum: the smallest value allowed; None: no bound.
        :param maximum: the largest value allowed; None: no bound.
        :param integer: read an int (Python's literal syntax: ``0x10`` too) rather than a float.
        :raises ConfigError: for text that is not such a number, a value that is not finite or
            out of bounds, or when it is absent without a default.
        """
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
