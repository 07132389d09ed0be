"""The stand-in steps aside where the underlay has the real tf2_msgs (ROS 2 from apt).

The detection (cmake/real_tf2_msgs.py) is tested on fake underlay prefixes in tmp_path; the
package's real CMakeLists.txt is then configured against such a prefix and must install nothing.
"""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(SOURCE / 'cmake'))

import real_tf2_msgs  # noqa: E402

INDEX = pathlib.Path('share', 'ament_index', 'resource_index')


def make_prefix(root: pathlib.Path, name: str, *, real: bool = False,
                standin: bool = False) -> pathlib.Path:
    """A fake install prefix whose ament index registers tf2_msgs (real or as a stand-in)."""
    prefix = root / name
    (prefix / INDEX / 'packages').mkdir(parents=True)
    (prefix / INDEX / 'packages' / 'geometry_msgs').touch()
    if real or standin:
        (prefix / INDEX / 'packages' / 'tf2_msgs').touch()
    if standin:
        (prefix / INDEX / 'wurde_standins').mkdir()
        (prefix / INDEX / 'wurde_standins' / 'tf2_msgs').write_text('stand-in')
    return prefix


def test_no_prefix_has_it(tmp_path: pathlib.Path) -> None:
    venv = make_prefix(tmp_path, 'venv')
    assert real_tf2_msgs.find_real([str(venv), str(tmp_path / 'missing')]) is None


def test_real_one_found_after_others(tmp_path: pathlib.Path) -> None:
    venv = make_prefix(tmp_path, 'venv')
    opt_ros = make_prefix(tmp_path, 'opt_ros_jazzy', real=True)
    assert real_tf2_msgs.find_real(['', str(venv), str(opt_ros)]) == opt_ros


def test_first_real_one_wins(tmp_path: pathlib.Path) -> None:
    first = make_prefix(tmp_path, 'first', real=True)
    second = make_prefix(tmp_path, 'second', real=True)
    assert real_tf2_msgs.find_real([str(first), str(second)]) == first


def test_a_standin_of_another_workspace_is_not_the_real_one(tmp_path: pathlib.Path) -> None:
    other_workspace = make_prefix(tmp_path, 'main_install_tf2_msgs', standin=True)
    assert real_tf2_msgs.find_real([str(other_workspace)]) is None


def test_own_install_prefix_is_excluded(tmp_path: pathlib.Path) -> None:
    own = make_prefix(tmp_path, 'own', real=True)
    link = tmp_path / 'own_link'
    link.symlink_to(own)
    assert real_tf2_msgs.find_real([str(link)], exclude=[str(own)]) is None
    opt_ros = make_prefix(tmp_path, 'opt', real=True)
    assert real_tf2_msgs.find_real([str(link), str(opt_ros)], exclude=[str(own)]) == opt_ros


@pytest.mark.process
def test_command_line_reads_ament_prefix_path(tmp_path: pathlib.Path) -> None:
    opt_ros = make_prefix(tmp_path, 'opt', real=True)
    script = SOURCE / 'cmake' / 'real_tf2_msgs.py'
    env = dict(os.environ, AMENT_PREFIX_PATH=os.pathsep.join([str(tmp_path / 'x'), str(opt_ros)]))
    found = subprocess.run([sys.executable, str(script)], env=env, capture_output=True,
                           text=True, check=True, timeout=30)
    assert found.stdout.strip() == str(opt_ros)
    none = subprocess.run([sys.executable, str(script), '--exclude', str(opt_ros)], env=env,
                          capture_output=True, text=True, check=True, timeout=30)
    assert none.stdout == ''


def configure(tmp_path: pathlib.Path, underlay: pathlib.Path,
              install: pathlib.Path) -> subprocess.CompletedProcess[str]:
    """Configure this package's CMakeLists.txt with ``underlay`` first on AMENT_PREFIX_PATH."""
    cmake = shutil.which('cmake')
    assert cmake is not None, 'cmake is not on PATH'
    env = dict(os.environ, AMENT_PREFIX_PATH=os.pathsep.join(
        [str(underlay), os.environ.get('AMENT_PREFIX_PATH', '')]))
    return subprocess.run(
        [cmake, '-S', str(SOURCE), '-B', str(tmp_path / 'build'),
         f'-DCMAKE_INSTALL_PREFIX={install}'],
        env=env, capture_output=True, text=True, timeout=120)


@pytest.mark.process
def test_package_installs_nothing_over_a_real_underlay(tmp_path: pathlib.Path) -> None:
    opt_ros = make_prefix(tmp_path, 'opt_ros_jazzy', real=True)
    install = tmp_path / 'install'
    result = configure(tmp_path, opt_ros, install)
    assert result.returncode == 0, result.stderr
    assert f'the real tf2_msgs is installed in {opt_ros}' in result.stdout
    installed = subprocess.run([shutil.which('cmake') or 'cmake', '--install',
                                str(tmp_path / 'build')],
                               capture_output=True, text=True, timeout=60)
    assert installed.returncode == 0, installed.stderr
    assert not install.exists() or not any(install.iterdir())


@pytest.mark.process
def test_a_standin_left_in_the_install_prefix_is_refused(tmp_path: pathlib.Path) -> None:
    opt_ros = make_prefix(tmp_path, 'opt_ros_jazzy', real=True)
    stale = make_prefix(tmp_path, 'install', standin=True)
    result = configure(tmp_path, opt_ros, stale)
    assert result.returncode != 0
    assert 'still holds this stand-in' in result.stderr


@pytest.mark.parametrize('standin', [False, True])
def test_standin_marker_decides(tmp_path: pathlib.Path, standin: bool) -> None:
    prefix = make_prefix(tmp_path, 'p', real=not standin, standin=standin)
    assert real_tf2_msgs.provides_real(prefix) is not standin
    assert real_tf2_msgs.is_standin(prefix) is standin
