"""What the manual (docs/many-machines.md) says of DDS Security (issue 16) holds for this install:
the Fast DDS library the ROS wheels bring has no builtin security plugins.  When a wheel with
security comes, this test fails, and that section and a keystore set-up are due."""

from __future__ import annotations

import os
import pathlib

#: The names Fast DDS registers its builtin security plugins under (DDS Security 1.1, 8.x).
PLUGINS = (b'DDS:Auth:PKI-DH', b'DDS:Access:Permissions', b'DDS:Crypto:AES-GCM-GMAC')


def _fast_dds_libraries() -> list[pathlib.Path]:
    found = []
    for prefix in filter(None, os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep)):
        found += sorted(pathlib.Path(prefix, 'lib').glob('libfast*.so*'))
    return [path for path in found if not path.is_symlink()]


def test_the_wheels_fast_dds_has_no_dds_security() -> None:
    libraries = _fast_dds_libraries()
    assert any(p.name.startswith(('libfastrtps.so', 'libfastdds.so')) for p in libraries), libraries
    for library in libraries:
        data = library.read_bytes()
        assert not [name for name in PLUGINS if name in data], \
            f'{library} has DDS Security built in: update docs/many-machines.md and add a keystore set-up'
    assert any(b'security is disabled' in p.read_bytes() for p in libraries)
