"""`make demo` (tools/demo.py): the MCP brings up config/pluto and the mission client sends the robot
through named places of the office by the navigator and explores a room, with a summary table and a
plot at the end — and goes on when a module is killed during the mission (the MCP starts it again)."""

from __future__ import annotations

import importlib.util
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys

import pytest
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
    # Part of the shipped mission (office2 through its 0.9 m door, its room explored, and back to
    # the start), with the live view beside it (test_live_view.py reads one with a Foxglove
    # client).  Once office2 is reached the laser's module is killed: the MCP starts it again and
    # the mission goes on (issue 13: a module killed during the demo).
    demo = subprocess.Popen([sys.executable, str(DEMO), '--config-dir', str(config), '--output', str(output),
                             '--places', 'office2,explore:office2,start', '--live', '0'],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines: list[str] = []
    killed = None
    assert demo.stdout is not None
    for line in demo.stdout:                  # ends when the demo ends (its timeout: 900 s)
        lines.append(line)
        if killed is None and line.startswith('mission: office2 (7.5, 3): reached'):
            started = [re.search(r'started PlutoLaser \(pid (\d+)\)', seen) for seen in lines]
            killed = int([m for m in started if m][-1].group(1))
            os.kill(killed, signal.SIGKILL)
    result = subprocess.CompletedProcess(demo.args, demo.wait(timeout=60), ''.join(lines), '')
    out = result.stdout
    said = [line for line in lines if line.startswith(('mission:', 'demo:', '│'))]
    assert result.returncode == 0, ''.join(said)[-6000:]
    assert killed is not None, 'office2 was not reached'
    restarted = re.findall(r'started PlutoLaser \(pid (\d+)\)', out)
    assert len(restarted) >= 2 and int(restarted[-1]) != killed, restarted
    assert 'mission: office2 (7.5, 3): reached' in out and 'mission: start (3, 7.5): reached' in out
    assert re.search(r'mission: explore:office2 \([\d.]+, [\d.]+\): reached', out)
    assert 'Mission summary' in out and '3 of 3' in out
    contacts = next(line for line in out.splitlines() if 'wall contacts' in line)
    assert contacts.split()[-2] == '0', contacts
    assert 'MCP exit 0' in out and 'record exit 0' in out and 'live_view ready on ws://127.0.0.1:' in out
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


def _demo_module():
    spec = importlib.util.spec_from_file_location('demo', DEMO)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize('people', [0, 1, 3])
def test_the_crowded_variant_puts_that_many_people_in_the_office(tmp_path: pathlib.Path, people: int) -> None:
    """`make demo DEMO_ARGS="--people N"`: config/pluto with N of config/pluto-people's people."""
    from wurde_drivers.sim.loading import load_sim
    target = _demo_module().prepared_config(PLUTO, tmp_path / 'config', None, people)
    config, world, _ = load_sim(str(target / 'sim-config.xml'))
    assert [p.name for p in config.people] == ['ana', 'ben', 'trolley'][:people]
    assert len(world.people) == people and config.time_scale == load_sim(str(PLUTO / 'sim-config.xml'))[0].time_scale


def test_more_people_than_the_crowded_variant_has_are_refused(tmp_path: pathlib.Path) -> None:
    with pytest.raises(SystemExit, match='--people takes 0 to 3'):
        _demo_module().prepared_config(PLUTO, tmp_path / 'config', None, 4)
