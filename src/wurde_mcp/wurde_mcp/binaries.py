"""Finding a module's binary (seed: WURDE Programming Guide 5.1.2 bin-directory, 6.1).

In order: an absolute path; the role configuration's bin-directory; the ament index
(``lib/<package>/<executable>``, so ``wurde_core/foo_server`` or just ``foo_server`` works as
``ros2 run`` would find it); then ``PATH``.
"""

from __future__ import annotations

import os
import pathlib
import shutil


def _executable(path: pathlib.Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)


def find_binary(binary: str, bin_directory: str = '') -> str | None:
    """The absolute path of ``binary``, or ``None`` when it is nowhere to be found.

    :param binary: an absolute path, ``package/executable`` (looked up as
        ``lib/package/executable`` under the ament prefixes), or an executable's name (under
        ``bin_directory``, then any package's ``lib/*/``, then ``PATH``).
    :param bin_directory: a directory searched first for a relative ``binary`` ('': none).
    """
    if not binary:
        return None
    candidate = pathlib.Path(binary)
    if candidate.is_absolute():
        return str(candidate) if _executable(candidate) else None
    if bin_directory:
        path = pathlib.Path(bin_directory) / binary
        if _executable(path):
            return str(path)
    prefixes = [pathlib.Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep)
                if p]
    if '/' in binary:
        package, _, name = binary.partition('/')
        for prefix in prefixes:
            path = prefix / 'lib' / package / name
            if _executable(path):
                return str(path)
    else:
        for prefix in prefixes:
            lib = prefix / 'lib'
            if not lib.is_dir():
                continue
            for path in sorted(lib.glob(f'*/{binary}')):
                if _executable(path):
                    return str(path)
    found = shutil.which(binary)
    return os.path.abspath(found) if found else None
