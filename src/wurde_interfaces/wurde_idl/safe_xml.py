"""The one hardened XML reader of the suite.

Every XML file the suite reads (interface definitions, role and MCP configuration, maps, device
configs) goes through :func:`parse_file`, which uses lxml with everything dangerous switched off:
no entity expansion, no network access, the DTD never loaded, a size cap, and any internal DTD
subset refused (that is where entity bombs and external entities are declared).  A plain
``<!DOCTYPE root SYSTEM "file.dtd">`` line, as every WURDE seed file starts with, is accepted and
its DTD is not read.
"""

from __future__ import annotations

import os
import pathlib
import re

from lxml import etree

from .errors import ConfigError

#: Largest XML file the suite reads; configuration and interface files are a few kilobytes.
MAX_XML_BYTES = 1 << 20

# A DOCTYPE whose declaration opens an internal subset: ``<!DOCTYPE root ... [``.
_INTERNAL_SUBSET = re.compile(rb'<!DOCTYPE[^>\[]*\[')


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_blank_text=False,
        remove_pis=True,
    )


def parse_bytes(data: bytes, path: str | os.PathLike[str], *, root_tag: str | tuple[str, ...],
                error: type[ConfigError] = ConfigError) -> etree._Element:
    """Parse ``data`` (read from ``path``) and return its root element.

    :param data: the document's bytes (more than :data:`MAX_XML_BYTES` are refused).
    :param path: the file they were read from, named in errors.
    :param root_tag: the root element's local name (namespace ignored), or the names allowed.
    :param error: the ConfigError subclass to raise (InterfaceError, MapError).
    :raises ConfigError: (or ``error``) naming ``path``, the line and the reason when the document
        is too large, not well formed, declares an internal DTD subset or entities, or has another
        root element.
    """
    if len(data) > MAX_XML_BYTES:
        raise error(path, None, f'file is {len(data)} bytes, larger than the {MAX_XML_BYTES} allowed')
    subset = _INTERNAL_SUBSET.search(data)
    if subset:
        raise error(path, data.count(b'\n', 0, subset.start()) + 1,
                    'a DOCTYPE with an internal subset ([...]) is refused: entity and DTD '
                    'declarations are not allowed')
    try:
        tree = etree.ElementTree(etree.fromstring(data, _parser()))
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if exc.lineno and exc.lineno > 0 else None
        raise error(path, line, f'not well-formed XML: {exc.msg}') from exc
    docinfo = tree.docinfo
    root = tree.getroot()
    for node in root.iter(etree.Entity):
        raise error(path, node.sourceline, f'entity reference {node.text} is refused')
    allowed = (root_tag,) if isinstance(root_tag, str) else tuple(root_tag)
    expected = ' or '.join(f'<{tag}>' for tag in allowed)
    if docinfo.root_name and docinfo.doctype and docinfo.root_name not in allowed:
        raise error(path, 1, f'DOCTYPE names <{docinfo.root_name}>, expected {expected}')
    local = etree.QName(root).localname
    if local not in allowed:
        raise error(path, root.sourceline, f'root element is <{local}>, expected {expected}')
    return root


def parse_file(path: str | os.PathLike[str], *, root_tag: str | tuple[str, ...],
               error: type[ConfigError] = ConfigError) -> etree._Element:
    """Read ``path`` and parse it with :func:`parse_bytes`.

    :param path: the file.
    :param root_tag: the root element's local name (namespace ignored), or the names allowed.
    :param error: the ConfigError subclass to raise (InterfaceError, MapError).
    :raises ConfigError: (or ``error``) when the file cannot be read or is refused.
    """
    file = pathlib.Path(path)
    try:
        size = file.stat().st_size
        if size > MAX_XML_BYTES:
            raise error(path, None, f'file is {size} bytes, larger than the {MAX_XML_BYTES} allowed')
        data = file.read_bytes()
    except OSError as exc:
        raise error(path, None, f'cannot read: {exc.strerror}') from exc
    return parse_bytes(data, path, root_tag=root_tag, error=error)
