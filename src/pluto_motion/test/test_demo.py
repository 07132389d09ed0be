"""`make demo` (tools/demo.py): the MCP brings up config/pluto and the mission client sends the robot
through named places of the office by moveto, with a summary table and a plot at the end."""

from __future__ import annotations

import pathlib
import shutil
import subprocess
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from wurde_core import topic

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
    assert 'MCP exit 0' in out and 'record exit 0' in out
    # The recording: every WURDE stream and the standard topics, decodable by an MCAP reader.
    with open(output / 'mission.mcap', 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        topics = {c.topic for c in reader.get_summary().channels.values()}
        assert {topic('Localization/Pose', 'data'), topic('motion/status', 'data'), '/tf', '/tf_static'} <= topics
        poses = [m for _, c, _, m in reader.iter_decoded_messages(topics=[topic('Localization/Pose', 'data')])]
    assert len(poses) > 100 and abs(poses[-1].pose.x - 3.0) < 0.5 and abs(poses[-1].pose.y - 7.5) < 0.5
    plot = output / 'mission.png'
    assert plot.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and plot.stat().st_size > 10_000
    for module in ('PlutoBase', 'localModule', 'motionModule'):
        assert (output / 'mcp-modules' / f'{module}.log').read_text().rstrip().endswith('--- exit code 0')
