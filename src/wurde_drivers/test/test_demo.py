"""`make demo` (tools/demo.py): the MCP brings up the dummy Pluto and the tour drives it round the office."""

from __future__ import annotations

import pathlib
import subprocess
import sys

from sim_fixture import ROOT, sim_config

DEMO = ROOT / 'tools' / 'demo.py'


def test_demo_tours_the_office_and_saves_a_plot(ros_domain: int, tmp_path: pathlib.Path) -> None:
    # The shipped config, four times as fast as real time so the test takes a quarter as long.
    config = sim_config(tmp_path / 'config', top={'time-scale': '4.0'}).parent
    output = tmp_path / 'out'
    result = subprocess.run([sys.executable, str(DEMO), '--config-dir', str(config), '--output', str(output)],
                            capture_output=True, text=True, timeout=600, check=False)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert 'tour: all of 8 waypoints reached' in result.stdout
    assert 'nearest thing ahead' in result.stdout
    assert 'MCP exit 0' in result.stdout
    plot = output / 'tour.png'
    assert plot.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and plot.stat().st_size > 10_000
    for module in ('PlutoBase', 'PlutoLaser', 'PlutoWrist', 'PlutoDMU', 'PlutoGPS'):
        assert (output / 'mcp-modules' / f'{module}.log').read_text().rstrip().endswith('--- exit code 0')
