"""Point the ROS 2 wheels' exported CMake files at this interpreter.

The ``ros-*`` wheels on PyPI were built with the manylinux Python at ``/opt/python/cp3X-cp3X``; their
``share/*/cmake/*Export.cmake`` files name that interpreter's include directory and numpy's include
directory, which do not exist here, so CMake stops with "includes non-existent path" as soon as a
package generates messages.  This rewrites those two paths to the running interpreter's include
directory and ``numpy.get_include()``.  It is idempotent: a second run changes nothing.

Usage: ``python tools/fix_ros_wheel_cmake.py <venv prefix>``
"""

from __future__ import annotations

import pathlib
import re
import sys
import sysconfig

import numpy

_PYTHON_INCLUDE = re.compile(r'/opt/python/cp3\d+-cp3\d+/include/python3\.\d+')
_NUMPY_INCLUDE = re.compile(
    r'/opt/python/cp3\d+-cp3\d+/lib/python3\.\d+/site-packages/numpy/(?:_?core)/include')


def fix(prefix: pathlib.Path) -> int:
    """Rewrite the stale paths under ``prefix/share``; return how many files changed."""
    python_include = sysconfig.get_paths()['include']
    numpy_include = numpy.get_include()
    changed = 0
    for cmake_file in sorted(prefix.glob('share/*/cmake/*.cmake')):
        text = cmake_file.read_text()
        if '/opt/python/' not in text:
            continue
        new = _NUMPY_INCLUDE.sub(numpy_include, text)
        new = _PYTHON_INCLUDE.sub(python_include, new)
        if new != text:
            cmake_file.write_text(new)
            changed += 1
    return changed


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    changed = fix(pathlib.Path(argv[1]))
    print(f'fix_ros_wheel_cmake: {changed} CMake file(s) pointed at {sys.executable}')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
