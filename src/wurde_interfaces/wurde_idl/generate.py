"""Build-time generator: interface XML files in, ``.msg`` files and descriptions out.

Called by the CMake function ``wurde_generate_interfaces`` at configure time::

    python -m wurde_idl generate --package PKG --output DIR file.xml ...

It writes ``DIR/msg/*.msg``, ``DIR/wurde/interfaces/*.json`` and ``DIR/interface_names.txt``,
prints the generated ``msg/*.msg`` paths (relative to ``DIR``) one per line for CMake, rewrites a
file only when its text changes (so an unchanged interface rebuilds nothing) and removes files
left from interfaces that no longer exist.  A refused file prints ``file:line: reason`` on stderr
and exits with status 1.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
from collections.abc import Sequence

from . import builtin_types, description, msg_writer
from .errors import WurdeError
from .reader import read_interfaces


def _write(path: pathlib.Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def generate(package: str, xml_files: Sequence[str], output: pathlib.Path,
             *, with_builtins: bool = False, installed: dict[str, str] | None = None,
             depends_digest: str = '') -> list[str]:
    """Generate everything for ``package``.

    :param package: the ROS package the messages belong to.
    :param xml_files: the package's interface files (read in sorted order).
    :param output: the directory written (``msg/``, ``wurde/interfaces/``,
        ``interface_names.txt``); files of interfaces no longer given are removed.
    :param with_builtins: also write the built-in types (only ``wurde_interfaces`` defines them).
    :param installed: names other packages already define, mapped to where; None: looked up in
        the ament index, so that a name is never defined twice.
    :param depends_digest: from the CMake macro, written into every interface message, so that
        a change in a dependency's messages changes this package's and rosidl rebuilds it.
    :returns: the written ``.msg`` paths, relative to ``output``.
    :raises WurdeError: when an interface file is refused.
    """
    if installed is None:
        installed = {name: f'installed package {desc["package"]} ({desc["source_file"]})'
                     for name, desc in description.load_all().items() if desc['package'] != package}
    interfaces = read_interfaces(sorted(xml_files), known=installed)
    msg_paths: list[str] = []
    keep: set[pathlib.Path] = set()
    for message, text in (builtin_types.builtin_messages() if with_builtins else {}).items():
        rel = f'msg/{message}.msg'
        _write(output / rel, text)
        keep.add(output / rel)
        msg_paths.append(rel)
    for interface in interfaces:
        for message, text in msg_writer.messages(interface, package, depends_digest).items():
            rel = f'msg/{message}.msg'
            _write(output / rel, text)
            keep.add(output / rel)
            msg_paths.append(rel)
        json_path = output / 'wurde' / 'interfaces' / f'{interface.name}.json'
        _write(json_path, json.dumps(description.to_json(interface, package), indent=2) + '\n')
        keep.add(json_path)
    names_path = output / 'interface_names.txt'
    _write(names_path, ''.join(f'{i.name}\n' for i in interfaces))
    for stale in list(output.glob('msg/*.msg')) + list(output.glob('wurde/interfaces/*.json')):
        if stale not in keep:
            stale.unlink()
    return msg_paths


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m wurde_idl generate|check``: see the module docstring and ``--help``.

    :param argv: the arguments after the program name; None: ``sys.argv[1:]``.
    :returns: the exit status: 0, or 1 after printing ``error: file:line: reason`` on stderr.
    """
    parser = argparse.ArgumentParser(prog='python -m wurde_idl', description=__doc__.split('\n')[0])
    sub = parser.add_subparsers(dest='command', required=True)
    gen = sub.add_parser('generate', help='generate .msg files and descriptions')
    gen.add_argument('--package', required=True, help='ROS package the messages belong to')
    gen.add_argument('--output', required=True, type=pathlib.Path, help='output directory')
    gen.add_argument('--builtins', action='store_true', help='also generate the built-in types')
    gen.add_argument('--depends-digest', default='',
                     help='digest of the dependencies\' interfaces, written into every .msg')
    gen.add_argument('xml_files', nargs='+', help='interface definition files')
    check = sub.add_parser('check', help='validate interface files, generate nothing')
    check.add_argument('xml_files', nargs='+')
    args = parser.parse_args(argv)
    try:
        if args.command == 'generate':
            for rel in generate(args.package, args.xml_files, args.output,
                                with_builtins=args.builtins,
                                depends_digest=args.depends_digest):
                print(rel)
        else:
            for interface in read_interfaces(args.xml_files):
                print(f'{interface.path}: interface {interface.name} {interface.version} ok')
    except WurdeError as exc:
        print(f'error: {exc}', file=sys.stderr)
        return 1
    return 0
