"""wrist_module end to end: the module as a real process in its no-hardware mode (emulate="true").

python-can's virtual bus connects buses inside one process only (docs/protocols.md 5), so the module
hosts the wrist emulator itself; the test commands it through its ActuatorState stream, exactly as
a client of the dummy wrist would, and silences the emulated modules with SIGUSR1 (the module's
fault switch in emulate mode). The last test brings up the shipped config/wrist under the MCP.
"""

from __future__ import annotations

import os
import pathlib
import signal
import time
from collections.abc import Iterator
from typing import Any

import pytest
from sim_fixture import Observer, assert_none_between, heartbeat
from wurde_testing import ChildProcess, find_executable

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'wrist'
EMULATED = '<device name="PlutoWrist" interface="virtual" channel="wrist" emulate="true"/>'


def wrist_config(directory: pathlib.Path, device: str = EMULATED) -> pathlib.Path:
    path = directory / 'wrist-config.xml'
    path.write_text(f'<?xml version="1.0"?>\n<wrist-config>\n  {device}\n</wrist-config>\n')
    return path


def wrist_module(config: pathlib.Path) -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'wrist_module'), '-c', str(config),
                         '-n', 'PlutoWrist'])


def logged(child: ChildProcess, prefix: str, text: str) -> int:
    """Lines of the module's own Logger (not the /rosout echo) that contain ``text``."""
    return sum(line.startswith(prefix) and text in line for line in child.stderr.splitlines())


def last(observer: Observer) -> Any:
    return observer.events['PlutoWrist'][-1][1]


def at(observer: Observer, pan: float, tilt: float) -> bool:
    """The newest state is at rest at (pan, tilt)."""
    if not observer.events['PlutoWrist']:
        return False
    state = last(observer)
    return (abs(state.position[0] - pan) < 1e-4 and abs(state.position[1] - tilt) < 1e-4
            and list(state.velocity) == [0.0, 0.0])


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({'PlutoWrist': 'ActuatorState', **heartbeat('PlutoWrist')})
    try:
        yield watcher
    finally:
        watcher.close()


def test_commands_move_the_emulated_wrist_and_the_state_follows(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    with wrist_module(wrist_config(tmp_path)) as child:
        observer.until(lambda o: at(o, 0.0, 0.0) and 'PlutoWrist' in o.infos, 'the wrist at rest')
        assert 'hosting the emulated wrist on virtual channel "wrist"' in child.stderr
        info = observer.infos['PlutoWrist']
        assert (list(info.position), list(info.velocity), list(info.acceleration)) == ([0, 0], [0, 0], [0, 0])
        start = len(observer.events['PlutoWrist'])
        observer.request('PlutoWrist', cmd_flags=0, position=[0.5, -0.3], velocity=[1.0, 0.5],
                         acceleration=[4.0, 4.0])
        observer.until(lambda o: at(o, 0.5, -0.3), 'the wrist at (0.5, -0.3)', timeout=10)
        info = observer.infos['PlutoWrist']     # the command being executed
        assert [*info.position, *info.velocity, *info.acceleration] == pytest.approx(
            [0.5, -0.3, 1.0, 0.5, 4.0, 4.0])
        moving = [m for _, m in observer.events['PlutoWrist'][start:]]
        assert max(abs(m.velocity[0]) for m in moving) == pytest.approx(1.0, abs=0.05)   # cruising
        assert max(abs(m.velocity[1]) for m in moving) == pytest.approx(0.5, abs=0.05)
        assert max(abs(m.acceleration[0]) for m in moving) > 1.0
        stamps = observer.stamps('PlutoWrist')
        assert all(b > a for a, b in zip(stamps, stamps[1:])) and abs(stamps[-1] - time.time()) < 5

        # Pluto 8.3: without velocity and acceleration > 0 an axis keeps its position.
        observer.request('PlutoWrist', cmd_flags=0, position=[-0.5, 0.3], velocity=[2.0, 0.0],
                         acceleration=[8.0, 8.0])
        observer.until(lambda o: at(o, -0.5, -0.3), 'pan moved, tilt stayed', timeout=10)
        assert list(observer.infos['PlutoWrist'].position) == pytest.approx([-0.5, -0.3])

        # cmdFlags < 0 halts: the wrist stops short of a slow move's target.
        observer.request('PlutoWrist', cmd_flags=0, position=[1.5, -0.3], velocity=[0.3, 1.0],
                         acceleration=[4.0, 4.0])
        observer.until(lambda o: last(o).position[0] > -0.3, 'the slow move under way', timeout=10)
        observer.request('PlutoWrist', cmd_flags=-1)
        observer.until(lambda o: list(o.infos['PlutoWrist'].velocity) == [0, 0] and
                       last(o).velocity[0] == 0.0, 'halted', timeout=10)
        halted_at = last(observer).position[0]
        assert -0.3 < halted_at < 1.4
        assert list(observer.infos['PlutoWrist'].position) == pytest.approx([halted_at, -0.3], abs=0.05)


def test_silent_modules_are_logged_and_no_state_is_published_until_they_are_back(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    with wrist_module(wrist_config(tmp_path)) as child:
        observer.until(lambda o: len(o.events['PlutoWrist']) >= 5, 'states before the silence')
        child.process.send_signal(signal.SIGUSR1)          # the emulated modules fall silent
        observer.until(lambda o: logged(child, '[WARN] PlutoWrist:', 'are silent') == 1,
                       'the silence logged', timeout=10)
        # Every state read before the silence was published before it was logged; the module
        # runs a few loop turns while they are silent, in which it must publish nothing.
        quiet = observer.quiet_span('PlutoWrist', 'loop turns while silent')
        child.process.send_signal(signal.SIGUSR1)          # and answer again
        back = time.time()
        observer.until(lambda o: logged(child, '[NOTICE] PlutoWrist:', 'are back') == 1 and sum(
            s > back for s in o.stamps('PlutoWrist')) >= 5, 'states again', timeout=10)
        assert logged(child, '[WARN] PlutoWrist:', 'are silent') == 1    # logged once
        assert at(observer, 0.0, 0.0)
    # States from after the silence arrived, so all before them did: none is of the silence.
    assert_none_between(observer.stamps('PlutoWrist'), quiet, back, 'wrist states while silent')


@pytest.mark.parametrize(('device', 'reason'), [
    ('<device name="PlutoWrist" interface="socketcan" channel="can0" emulate="true"/>',
     ':3: emulate="true" needs interface="virtual"'),
    ('<device name="OtherWrist" interface="virtual" channel="wrist"/>',
     ': no <device> named "PlutoWrist"'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                     device: str, reason: str) -> None:
    path = wrist_config(tmp_path, device)
    with wrist_module(path) as child:
        assert child.process.wait(timeout=30) == 2
    assert f'wrist_module: {path}{reason}' in child.stderr


def test_the_shipped_config_runs_the_emulated_wrist_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    for name in ('wrist-config.xml', 'mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_bytes((CONFIG / name).read_bytes())
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: at(o, 0.0, 0.0), 'the wrist at rest', timeout=30)
        observer.request('PlutoWrist', cmd_flags=0, position=[0.2, 0.1], velocity=[2.0, 2.0],
                         acceleration=[8.0, 8.0])
        observer.until(lambda o: at(o, 0.2, 0.1), 'the wrist at (0.2, 0.1)', timeout=10)
        mcp.stop(timeout=30)
    log = (tmp_path / 'mcp-modules' / 'PlutoWrist.log').read_text()
    assert log.rstrip().endswith('--- exit code 0'), log[-2000:]
