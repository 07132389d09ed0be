"""The hardened XML reader refuses hostile documents and accepts the seeds' DOCTYPE lines."""

from __future__ import annotations

import pathlib

import pytest

from wurde_idl import ConfigError, parse_bytes, parse_file
from wurde_idl.safe_xml import MAX_XML_BYTES

BILLION_LAUGHS = b'''<?xml version="1.0"?>
<!DOCTYPE interface [
  <!ENTITY lol "lol">
  <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
  <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
]>
<interface name="Bomb" version="1.0"><author>&lol3;</author></interface>
'''

EXTERNAL_ENTITY = b'''<?xml version="1.0"?>
<!DOCTYPE interface [ <!ENTITY secret SYSTEM "file:///etc/passwd"> ]>
<interface name="Leak" version="1.0"><author>&secret;</author></interface>
'''


def test_entity_bomb_is_refused_at_its_doctype_line() -> None:
    with pytest.raises(ConfigError, match='internal subset') as caught:
        parse_bytes(BILLION_LAUGHS, 'bomb.xml', root_tag='interface')
    assert caught.value.line == 2 and caught.value.path == 'bomb.xml'


def test_external_entity_is_refused() -> None:
    with pytest.raises(ConfigError, match='internal subset'):
        parse_bytes(EXTERNAL_ENTITY, 'leak.xml', root_tag='interface')


def test_undeclared_entity_reference_is_refused() -> None:
    with pytest.raises(ConfigError, match='not well-formed') as caught:
        parse_bytes(b'<interface>\n<author>&nope;</author></interface>', 'x.xml',
                    root_tag='interface')
    assert caught.value.line == 2


def test_seed_doctype_is_accepted_and_its_dtd_never_read(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'ok.xml'
    path.write_bytes(b'<?xml version="1.0"?>\n<!DOCTYPE interface SYSTEM '
                     b'"http://127.0.0.1:9/never-fetched.dtd">\n<interface name="A"/>\n')
    root = parse_file(path, root_tag='interface')
    assert root.get('name') == 'A'


def test_file_over_the_size_cap_is_refused_before_reading(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'huge.xml'
    with path.open('wb') as out:
        out.write(b'<interface>')
        out.write(b' ' * MAX_XML_BYTES)
        out.write(b'</interface>')
    with pytest.raises(ConfigError, match='larger than'):
        parse_file(path, root_tag='interface')


def test_missing_file_names_the_file(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_file(tmp_path / 'absent.xml', root_tag='interface')
    assert caught.value.path.endswith('absent.xml') and 'cannot read' in caught.value.reason
