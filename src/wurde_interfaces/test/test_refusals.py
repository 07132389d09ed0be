"""Every kind of bad interface file is refused with file, line and reason."""

from __future__ import annotations

import pathlib
import subprocess
import sys
import textwrap

import pytest

from wurde_idl import InterfaceError, read_interface, read_interfaces

HEAD = '<?xml version="1.0"?>\n<!DOCTYPE interface SYSTEM "include/interface.dtd">\n'


def interface(body: str, name: str = 'Thing', attrs: str = 'version="1.0"') -> str:
    """An interface file; line 4 is the first line of ``body``."""
    return (HEAD + f'<interface name="{name}" {attrs}>\n'
            + textwrap.dedent(body).strip('\n') + '\n</interface>\n')


GOOD_HEAD = '<author>A</author>\n<description>D</description>\n'

CASES = {
    'unknown tag': (interface(GOOD_HEAD + '<subscribe/>\n'), 6, 'unknown tag <subscribe>'),
    'unknown attribute': (interface(GOOD_HEAD + '<info>\n<data name="a" type="Float" unit="m"/>\n'
                                    '</info>'), 7, 'unknown attribute(s) unit on <data>'),
    'unknown type': (interface(GOOD_HEAD + '<publish>\n<data name="a" type="Quaternion"/>\n'
                               '</publish>'), 7, 'unknown type "Quaternion"'),
    'bad member identifier': (interface(GOOD_HEAD + '<info>\n<data name="max-range" type="Float"/>'
                                        '\n</info>'), 7, 'member name "max-range"'),
    'member starting with a digit': (interface(GOOD_HEAD + '<info>\n<data name="2d" type="Float"/>'
                                               '\n</info>'), 7, 'member name "2d"'),
    'double underscore': (interface(GOOD_HEAD + '<info>\n<data name="a__b" type="Float"/>\n</info>'),
                          7, 'not valid'),
    'reserved member': (interface(GOOD_HEAD + '<info>\n<data name="header" type="Float"/>\n</info>'),
                        7, 'reserved'),
    'python keyword': (interface(GOOD_HEAD + '<info>\n<data name="lambda" type="Float"/>\n</info>'),
                       7, 'Python keyword'),
    'names that collide in snake_case': (
        interface(GOOD_HEAD + '<info>\n<data name="maxRange" type="Float"/>\n'
                  '<data name="max_range" type="Float"/>\n</info>'), 8, 'both become ROS field'),
    'duplicate member': (interface(GOOD_HEAD + '<info>\n<data name="a" type="Float"/>\n'
                                   '<data name="a" type="Float"/>\n</info>'), 8, 'defined twice'),
    'array_size naming a missing member': (
        interface(GOOD_HEAD + '<publish>\n<data name="ranges" type="Double" array_size="n"/>\n'
                  '</publish>'), 7, 'array_size "n" of member "ranges" names no member'),
    'array_size naming a non-integer': (
        interface(GOOD_HEAD + '<publish>\n<data name="n" type="Double"/>\n'
                  '<data name="ranges" type="Double" array_size="n"/>\n</publish>'), 8,
        'must name an integer member'),
    'missing author': (interface('<description>D</description>\n'), 3, 'no <author> section'),
    'missing description': (interface('<author>A</author>\n'), 3, 'no <description> section'),
    'empty author': (interface('<author> </author>\n<description>D</description>\n'), 4,
                     '<author> is empty'),
    'second info section': (interface(GOOD_HEAD + '<info/>\n<info/>\n'), 7,
                            'a second <info> section'),
    'second publish section': (interface(GOOD_HEAD + '<publish/>\n<publish/>\n'), 7,
                               'a second <publish> section'),
    'missing version': (interface(GOOD_HEAD, attrs=''), 3, '<interface> needs non-empty attribute(s) version'),
    'bad version': (interface(GOOD_HEAD, attrs='version="one"'), 3, 'must look like 1.0'),
    'lower-case interface name': (interface(GOOD_HEAD, name='thing'), 3, 'must be PascalCase'),
    'type named like a built-in': (interface(GOOD_HEAD + '<type name="Pose">\n'
                                             '<data name="a" type="Float"/>\n</type>'), 6,
                                   'is a built-in type'),
    'type defined twice': (interface(GOOD_HEAD + '<type name="A">\n<data name="a" type="Float"/>'
                                     '\n</type>\n<type name="A">\n<data name="a" type="Float"/>\n'
                                     '</type>'), 9, 'defined twice'),
    'types in a cycle': (interface(GOOD_HEAD + '<type name="A">\n<data name="b" type="B"/>\n</type>'
                                   '\n<type name="B">\n<data name="a" type="A"/>\n</type>'), 6,
                         'cycle: A -> B -> A'),
    'data outside a section': (interface(GOOD_HEAD + '<data name="a" type="Float"/>\n'), 6,
                               'unknown tag <data>'),
    'stray text': (interface(GOOD_HEAD + 'hello\n'), 5, 'stray text'),
    'not well formed': (HEAD + '<interface name="Thing" version="1.0">\n<author>A</author>\n'
                        '<description>D</descr>\n</interface>\n', 5, 'not well-formed XML'),
    'wrong root': (HEAD.replace('interface SYSTEM', 'config SYSTEM') + '<config/>\n', 1,
                   'DOCTYPE names <config>'),
    'wrong root without doctype': ('<?xml version="1.0"?>\n<module name="x"/>\n', 2,
                                   'root element is <module>'),
}


@pytest.mark.parametrize('case', sorted(CASES))
def test_bad_file_is_refused_with_file_line_and_reason(case: str, tmp_path: pathlib.Path) -> None:
    text, line, reason = CASES[case]
    path = tmp_path / 'Thing.xml'
    path.write_text(text)
    with pytest.raises(InterfaceError) as caught:
        read_interface(path)
    error = caught.value
    assert error.path == str(path)
    assert error.line == line, str(error)
    assert reason in error.reason, str(error)
    assert str(error).startswith(f'{path}:{line}: ')


def write(path: pathlib.Path, name: str, type_name: str = 'Extra') -> pathlib.Path:
    path.write_text(interface(GOOD_HEAD + f'<type name="{type_name}">\n'
                              '<data name="a" type="Float"/>\n</type>', name=name))
    return path


def test_duplicate_interface_name_is_refused(tmp_path: pathlib.Path) -> None:
    first = write(tmp_path / 'a.xml', 'Thing', 'One')
    second = write(tmp_path / 'b.xml', 'Thing', 'Two')
    with pytest.raises(InterfaceError) as caught:
        read_interfaces([first, second])
    assert caught.value.path == str(second)
    assert caught.value.line == 3
    assert f'already defined by {first}:3' in caught.value.reason


def test_duplicate_type_name_across_files_is_refused(tmp_path: pathlib.Path) -> None:
    first = write(tmp_path / 'a.xml', 'Thing', 'Shared')
    second = write(tmp_path / 'b.xml', 'Other', 'Shared')
    with pytest.raises(InterfaceError) as caught:
        read_interfaces([first, second])
    assert caught.value.path == str(second) and caught.value.line == 6
    assert '"Shared" is already defined' in caught.value.reason


def test_name_taken_by_an_installed_package_is_refused(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path / 'a.xml', 'Foo')
    with pytest.raises(InterfaceError, match='already defined by installed wurde_interfaces'):
        read_interfaces([path], known={'Foo': 'installed wurde_interfaces (Foo.xml)'})


def test_type_clashing_with_generated_message_is_refused(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path / 'a.xml', 'Thing', 'ThingData')
    with pytest.raises(InterfaceError, match='clashes with the messages of interface "Thing"'):
        read_interface(path)


@pytest.mark.process
def test_command_line_reports_file_line_reason_and_fails(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'Thing.xml'
    text, line, reason = CASES['unknown type']
    path.write_text(text)
    result = subprocess.run(
        [sys.executable, '-m', 'wurde_idl', 'generate', '--package', 'p', '--output',
         str(tmp_path / 'out'), str(path)], capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 1
    assert f'{path}:{line}: ' in result.stderr and reason in result.stderr
    assert not (tmp_path / 'out' / 'msg').exists()
