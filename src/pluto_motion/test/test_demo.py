"""`make demo` (tools/demo.py): the MCP brings up config/pluto and the mission client sends the robot
through named places of the office by moveto, with a summary table and a plot at the end."""

from __future__ import annotations

import pathlib
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[3]
DEMO = ROOT / 'tools' / 'demo.py'
PLUTO = ROOT / 'config' / 'pluto'


def test_demo_visits_places_by_name_and_saves_a_plot(ros_domain: int, tmp_path: pathlib.Path) -> None:
    config = tmp_path / 'config'
    config.mkdir()
    for name in ('mcp-config.xml', 'mcp-mappings.xml', 'map.xml', 'sim-config.xml'):
        shutil.copy(PLUTO / name, config / name)
    output = tmp_path / 'out'
    # Two places of the shipped mission (office2 through its 0.9 m door, and back to the start).
    result = subprocess.run([sys.executable, str(DEMO), '--config-dir', str(config), '--output', str(output),
                             '--places', 'office2,start'],
                            capture_output=True, text=True, timeout=900, check=False)
    out = result.stdout
    assert result.returncode == 0, out[-4000:] + result.stderr[-3000:]
    assert 'mission: office2 (7.5, 3): reached' in out and 'mission: start (3, 7.5): reached' in out
    assert 'Mission summary' in out and '2 of 2' in out
    contacts = next(line for line in out.splitlines() if 'wall contacts' in line)
    assert contacts.split()[-2] == '0', contacts
    assert 'MCP exit 0' in out
    plot = output / 'mission.png'
    assert plot.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and plot.stat().st_size > 10_000
    for module in ('PlutoBase', 'localModule', 'motionModule'):
        assert (output / 'mcp-modules' / f'{module}.log').read_text().rstrip().endswith('--- exit code 0')
