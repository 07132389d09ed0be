"""Find the real tf2_msgs in the underlay, so that this stand-in can step aside.

The stand-in exists only because the ROS 2 wheels on PyPI lack tf2_msgs.  Where the ROS install
has it (ROS 2 from apt: ``/opt/ros/jazzy``), the real package must be used: an overlay of this
message-only package would hide upstream's services and actions (``tf2_ros`` imports
``tf2_msgs.action``).  CMakeLists.txt runs this script at configure time and builds and installs
nothing when it prints a prefix.

A prefix provides the real tf2_msgs when the ament index there registers the package
(``share/ament_index/resource_index/packages/tf2_msgs``) and does not mark it as a stand-in
(``share/ament_index/resource_index/wurde_standins/tf2_msgs``, which this package installs), so
a stand-in built by another workspace of this project, used as underlay, never counts.  The
prefixes searched are those of ``AMENT_PREFIX_PATH`` (the ament index's search path), in order,
less the ones excluded (this package's own install prefix).

Usage: ``python real_tf2_msgs.py [--exclude PREFIX]...``; prints the prefix, or nothing, and
exits 0.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
from collections.abc import Iterable, Sequence

PACKAGE = 'tf2_msgs'
#: The ament index resource type under which this workspace marks its stand-in packages.
STANDIN_RESOURCE_TYPE = 'wurde_standins'
_INDEX = pathlib.Path('share', 'ament_index', 'resource_index')


def is_standin(prefix: pathlib.Path, package: str = PACKAGE) -> bool:
    """Whether ``prefix`` holds this workspace's stand-in for ``package``."""
    return (prefix / _INDEX / STANDIN_RESOURCE_TYPE / package).is_file()


def provides_real(prefix: pathlib.Path, package: str = PACKAGE) -> bool:
    """Whether the ament index under ``prefix`` registers ``package`` and it is no stand-in."""
    return (prefix / _INDEX / 'packages' / package).is_file() and not is_standin(prefix, package)


def _same(a: pathlib.Path, b: pathlib.Path) -> bool:
    try:
        return a.resolve() == b.resolve()
    except OSError:
        return False


def find_real(search_path: Iterable[str], exclude: Sequence[str] = (),
              package: str = PACKAGE) -> pathlib.Path | None:
    """The first prefix of ``search_path`` that provides the real ``package``, else None.

    :param search_path: prefixes in lookup order (``AMENT_PREFIX_PATH`` split); empty entries
        are ignored.
    :param exclude: prefixes never to report (this package's own install prefix).
    """
    excluded = [pathlib.Path(p) for p in exclude if p]
    for entry in search_path:
        if not entry:
            continue
        prefix = pathlib.Path(entry)
        if any(_same(prefix, other) for other in excluded):
            continue
        if provides_real(prefix, package):
            return prefix
    return None


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--exclude', action='append', default=[], metavar='PREFIX',
                        help='a prefix never to report (repeatable)')
    args = parser.parse_args(argv)
    found = find_real(os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep), args.exclude)
    if found is not None:
        print(found)
    return 0


if __name__ == '__main__':
    sys.exit(main())
