"""The README's pluto_nav examples run as written: the estimation core in process, and the
where_am_i client against config/pluto under the MCP."""

from __future__ import annotations

import contextlib
import io
import os
import pathlib
import re

import pytest
from nav_fixture import pluto_config
from wurde_testing import ChildProcess, find_executable

README = pathlib.Path(__file__).resolve().parents[3] / 'README.md'


def test_readme_example_localizes_the_laser_and_finds_the_wall():
    text = README.read_text()
    (code,) = re.findall(r'<!-- example: pluto_nav -->\n```python\n(.*?)```', text, re.S)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, 'README.md', 'exec'), {})
    assert out.getvalue().splitlines() == ['4 True [4.  3.  0.1]', '89 -0.1 6.0']


def test_where_am_i_reads_the_pose_of_the_simulated_pluto_under_the_mcp(ros_domain: int,
                                                                       tmp_path: pathlib.Path) -> None:
    text = README.read_text()
    code = re.search(r'<!-- example: where_am_i -->\n```python\n(.*?)```', text, re.S).group(1)
    script = tmp_path / 'where_am_i.py'
    script.write_text(code)
    directory = pluto_config(tmp_path / 'pluto')     # config/pluto as shipped (its MCP config too)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory),
               WURDE_DATA_DIR=str(directory))     # the localModule's resume file goes there
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(directory / 'mcp-config.xml'),
                       '-m', str(directory / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=90)
        with ChildProcess([str(script)], env=env) as client:
            line = client.expect('setter', timeout=90)
            assert client.process.wait(timeout=30) == 0
    found = re.match(r'x (\S+) y (\S+) theta (\S+) setter (-?\d+)', line)
    assert found, line
    # The office's start place is (3, 7.5, 0); the robot has not moved.
    assert (float(found.group(1)), float(found.group(2)), float(found.group(3))) == \
        pytest.approx((3.0, 7.5, 0.0), abs=0.06)
    assert int(found.group(4)) in (0, 1)     # before or after the pose module took the setter


@pytest.mark.process
def test_readme_offline_nav_and_slam_score_run_as_printed(tmp_path: pathlib.Path) -> None:
    text = README.read_text()
    code = re.search(r'<!-- example: offline_nav -->\n```bash\n(.*?)```', text, re.S).group(1)
    code = code.replace('/tmp/fr079', str(tmp_path / 'fr079'))      # not the machine's /tmp
    with ChildProcess(['bash', '-ec', code], cwd=str(README.parent), python=False) as run:
        run.process.wait(timeout=300)
        assert run.stop() == 0, run.stderr
    assert re.search(r'1[23] pairs: translation 0\.0[0-5]\d+ m', run.stdout), run.stdout
    assert (tmp_path / 'fr079' / 'map.xml').exists() and (tmp_path / 'fr079' / 'map.pgm').exists()


def test_readme_offline_slam_in_python_beats_the_odometry(monkeypatch: pytest.MonkeyPatch) -> None:
    text = README.read_text()
    code = re.search(r'<!-- example: offline_slam -->\n```python\n(.*?)```', text, re.S).group(1)
    monkeypatch.chdir(README.parent)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, 'README.md', 'exec'), {})
    lines = out.getvalue().splitlines()
    errors = [float(re.search(r'translation (\S+) m', line).group(1)) for line in lines]
    assert lines[0].startswith('SLAM') and errors[0] < 0.8 * errors[1], lines
