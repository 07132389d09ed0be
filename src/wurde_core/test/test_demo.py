"""`make demo`'s main job (tools/demo.py) runs FooServer and FooClient and stops them cleanly."""

from __future__ import annotations

import pathlib
import subprocess
import sys

DEMO = pathlib.Path(__file__).resolve().parents[3] / 'tools' / 'demo.py'


def test_demo_runs_the_foo_pair_and_stops_cleanly(ros_domain: int) -> None:
    result = subprocess.run([sys.executable, str(DEMO)], capture_output=True, text=True,
                            timeout=120, check=False)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'Info: MaxRange 8.0' in result.stdout
    assert result.stdout.count('Val ') >= 5
    assert 'demo: both modules stopped cleanly' in result.stdout
