"""Golden-file tests of the generator on the WURDE Programming Guide's chapter 3 example."""

from __future__ import annotations

import json
import pathlib
import subprocess
import sys

import pytest

from wurde_idl import InterfaceError
from wurde_idl.generate import generate

HERE = pathlib.Path(__file__).parent
EXAMPLE = HERE / 'golden' / 'chapter3' / 'Foo.xml'
EXPECTED = HERE / 'golden' / 'chapter3' / 'expected'


def test_chapter3_example_generates_the_golden_messages(tmp_path: pathlib.Path) -> None:
    produced = generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    assert produced == ['msg/FooData.msg', 'msg/FooInfo.msg', 'msg/Pixel.msg']
    for name in ('FooData.msg', 'FooInfo.msg', 'Pixel.msg'):
        assert (tmp_path / 'msg' / name).read_text() == (EXPECTED / name).read_text(), name


def test_array_size_drops_the_count_member(tmp_path: pathlib.Path) -> None:
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    info = (tmp_path / 'msg' / 'FooInfo.msg').read_text()
    data = (tmp_path / 'msg' / 'FooData.msg').read_text()
    assert 'wurde_interfaces/Pose3D[] sensor_positions' in info
    assert ' range_count\n' not in info and 'int32 range_count' not in info
    assert 'example_pkg/Pixel[] image' in data
    assert 'int32 size' not in data


def test_boolean_is_accepted_for_bool(tmp_path: pathlib.Path) -> None:
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    assert 'bool uniform\n' in (tmp_path / 'msg' / 'FooInfo.msg').read_text()


def test_description_matches_golden(tmp_path: pathlib.Path) -> None:
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    got = json.loads((tmp_path / 'wurde' / 'interfaces' / 'Foo.json').read_text())
    assert got == json.loads((EXPECTED / 'Foo.json').read_text())
    assert got['dropped_count_members'] == {'Pixel': [], 'info': ['range_count'],
                                            'publish': ['size']}
    assert [m['name'] for m in got['types']['Pixel']] == ['r', 'g', 'b']


def test_second_run_rewrites_nothing(tmp_path: pathlib.Path) -> None:
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    before = {p: p.stat().st_mtime_ns for p in tmp_path.rglob('*') if p.is_file()}
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    after = {p: p.stat().st_mtime_ns for p in tmp_path.rglob('*') if p.is_file()}
    assert before == after


def test_stale_messages_are_removed(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'msg').mkdir()
    (tmp_path / 'msg' / 'GoneData.msg').write_text('int32 x\n')
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={})
    assert not (tmp_path / 'msg' / 'GoneData.msg').exists()


def test_builtins_are_generated_from_the_type_tables(tmp_path: pathlib.Path) -> None:
    produced = generate('example_pkg', [str(EXAMPLE)], tmp_path, with_builtins=True,
                        installed={})
    for name in ('Header', 'Lock', 'Point', 'Point3D', 'Pose', 'Pose3D', 'CVector', 'PVector',
                 'RunState', 'ProcessLocale', 'ProcessType', 'StatusMode', 'ConnectionStrategy'):
        assert f'msg/{name}.msg' in produced
    pose3d = (tmp_path / 'msg' / 'Pose3D.msg').read_text()
    assert [line.split()[1] for line in pose3d.splitlines() if line.startswith('float64')] == \
        ['x', 'y', 'z', 'theta', 'phi', 'psi', 'weight']
    run_state = (tmp_path / 'msg' / 'RunState.msg').read_text()
    assert 'uint8 RUN=0\n' in run_state and 'uint8 QUIT=4\n' in run_state


@pytest.mark.process
def test_command_line_prints_generated_paths(tmp_path: pathlib.Path) -> None:
    result = subprocess.run(
        # As package wurde_interfaces, so that the installed Foo is not a duplicate of this one.
        [sys.executable, '-m', 'wurde_idl', 'generate', '--package', 'wurde_interfaces',
         '--output', str(tmp_path), str(EXAMPLE)],
        capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ['msg/FooData.msg', 'msg/FooInfo.msg', 'msg/Pixel.msg']


def test_name_of_an_installed_interface_is_refused(tmp_path: pathlib.Path) -> None:
    """The installed wurde_interfaces already defines Foo: another package may not."""
    with pytest.raises(InterfaceError, match='"Foo" is already defined by installed package '
                       'wurde_interfaces'):
        generate('example_pkg', [str(EXAMPLE)], tmp_path)


def test_dependency_digest_marks_every_interface_message(tmp_path: pathlib.Path) -> None:
    """A dependency's changed messages must change ours, or rosidl keeps stale type hashes."""
    generate('example_pkg', [str(EXAMPLE)], tmp_path, installed={}, depends_digest='ab' * 32)
    for name in ('FooData.msg', 'FooInfo.msg', 'Pixel.msg'):
        text = (tmp_path / 'msg' / name).read_text()
        assert '# Built against dependency interfaces abababababababab.' in text
        assert text.replace('# Built against dependency interfaces abababababababab.\n', '') == \
            (EXPECTED / name).read_text()
