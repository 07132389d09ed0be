"""The pluto_nav examples of the README and the manual run as written: the README's tour (the MCP
bringing up config/pluto, and the where_am_i client), the estimation core in process, the offline
runs on a real robot's log."""

from __future__ import annotations

import contextlib
import io
import os
import pathlib
import re

import pytest
from wurde_testing import ChildProcess
from wurde_testing.manual import example, repository_root

ROOT = repository_root()


def test_readme_example_localizes_the_laser_and_finds_the_wall():
    code = example('pluto_nav', 'python')
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, 'docs/navigation.md', 'exec'), {})
    assert out.getvalue().splitlines() == ['4 True [4.  3.  0.1]', '89 -0.1 6.0']


def test_the_readme_tour_brings_up_pluto_and_the_client_says_where_it_is(ros_domain: int,
                                                                          tmp_path: pathlib.Path) -> None:
    """The tour's shell lines as printed, in a directory that holds the client as where_am_i.py and
    the workspace's env.sh, .venv, install and config (links), the data directory in tmp_path."""
    block = example('tour', 'bash')
    assert block.startswith('source env.sh')
    (tmp_path / 'where_am_i.py').write_text(example('where_am_i', 'python'))
    for name in ('env.sh', '.venv', 'install', 'config'):
        (tmp_path / name).symlink_to(ROOT / name)
    data = tmp_path / 'data'
    env = dict(os.environ, WURDE_DATA_DIR=str(data), WURDE_LOG_DIRECTORY=str(data))
    with ChildProcess(['bash', '-ec', block], cwd=str(tmp_path), env=env, python=False) as tour:
        line = tour.expect('setter', timeout=150)
        assert tour.process.wait(timeout=60) == 0, tour.stderr
    found = re.match(r'x (\S+) y (\S+) theta (\S+) setter (-?\d+)', line)
    assert found, line
    # The office's start place is (3, 7.5, 0); the robot has not moved.
    assert (float(found.group(1)), float(found.group(2)), float(found.group(3))) == \
        pytest.approx((3.0, 7.5, 0.0), abs=0.06)
    assert int(found.group(4)) in (0, 1)     # before or after the pose module took the setter
    # The MCP ended its modules on the shell's SIGINT, each with its log in the data directory.
    assert (data / 'mcp-modules' / 'localModule.log').read_text().rstrip().endswith('--- exit code 0')


@pytest.mark.process
def test_readme_offline_nav_and_slam_score_run_as_printed(tmp_path: pathlib.Path) -> None:
    code = example('offline_nav', 'bash')
    code = code.replace('/tmp/fr079', str(tmp_path / 'fr079'))      # not the machine's /tmp
    with ChildProcess(['bash', '-ec', code], cwd=str(ROOT), python=False) as run:
        run.process.wait(timeout=300)
        assert run.stop() == 0, run.stderr
    assert re.search(r'1[23] pairs: translation 0\.0[0-5]\d+ m', run.stdout), run.stdout
    assert (tmp_path / 'fr079' / 'map.xml').exists() and (tmp_path / 'fr079' / 'map.pgm').exists()


def test_readme_offline_slam_in_python_beats_the_odometry(monkeypatch: pytest.MonkeyPatch) -> None:
    code = example('offline_slam', 'python')
    monkeypatch.chdir(ROOT)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, 'docs/real-data.md', 'exec'), {})
    lines = out.getvalue().splitlines()
    errors = [float(re.search(r'translation (\S+) m', line).group(1)) for line in lines]
    assert lines[0].startswith('SLAM') and errors[0] < 0.8 * errors[1], lines
