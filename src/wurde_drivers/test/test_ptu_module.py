"""ptu_server end to end: the PTU Server as a real process against the emulated PTU-46 on a pty.

The emulator runs in the test process (so the test sees the unit's own position and controls its
silence); the module is a child process with ``-c`` a ptu-config in tmp naming the emulator's
pty. The last test brings up the shipped config/ptu (emulator program and server) under the MCP.
"""

from __future__ import annotations

import math
import os
import pathlib
import time
from collections.abc import Iterator

import pytest
from sim_fixture import Observer, assert_none_between, heartbeat, median_interval
from wurde_core import LockedError
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.ptu.emulator import Ptu46Emulator

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'ptu'
STEP = 185.1428 / 3600.0 * math.pi / 180.0     # rad per position step of the emulated unit


def ptu_config(directory: pathlib.Path, port: str, *, device: str | None = None) -> pathlib.Path:
    path = directory / 'ptu-config.xml'
    device = device or f'<device port="{port}" name="PTU" rate="10"/>'
    path.write_text(f'<?xml version="1.0"?>\n<ptu-config>\n  {device}\n</ptu-config>\n')
    return path


def ptu_server(config: pathlib.Path, name: str = 'PTU') -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'ptu_server'), '-c', str(config),
                         '-n', name])


def logged(child: ChildProcess, level: str, text: str) -> int:
    """Lines of the module's own Logger (not the /rosout echo) that contain ``text``."""
    return sum(line.startswith(f'[{level}] PTU:') and text in line
               for line in child.stderr.splitlines())


def latest(observer: Observer) -> object:
    return observer.events['PTU'][-1][1]


@pytest.fixture
def unit() -> Iterator[Ptu46Emulator]:
    with Ptu46Emulator() as emulator:
        yield emulator
    assert emulator.error is None


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({'PTU': 'PTUnit', **heartbeat('PTU')})
    try:
        yield watcher
    finally:
        watcher.close()


def test_requests_move_the_unit_and_the_data_follows(unit: Ptu46Emulator, observer: Observer,
                                                      tmp_path: pathlib.Path) -> None:
    with ptu_server(ptu_config(tmp_path, unit.path)) as child:
        observer.until(lambda o: 'PTU' in o.infos and len(o.events['PTU']) >= 3, 'info and data')
        info = observer.infos['PTU']
        # The emulated unit's limits (PTU-D46 manual: -3090..3090 pan, -907..604 tilt).
        assert (info.pan_min, info.pan_max) == pytest.approx((-3090 * STEP, 3090 * STEP))
        assert (info.tilt_min, info.tilt_max) == pytest.approx((-907 * STEP, 604 * STEP))
        assert info.pan_resolution == pytest.approx(STEP) and not info.velocity_mode
        # Read-only members are locked to suppliers: a consumer's write is refused at once.
        with pytest.raises(LockedError):
            observer.obj('PTU').requests.pan_max.set_value(10.0)
        # Position mode; the pan beyond its limit is clamped, the info says what was commanded.
        observer.request('PTU', pan=10.0, tilt=-0.3, pan_speed=2.5, tilt_speed=1.0)
        observer.until(lambda o: o.infos['PTU'].pan == pytest.approx(3090 * STEP), 'clamped info')
        info = observer.infos['PTU']
        assert info.tilt == pytest.approx(round(-0.3 / STEP) * STEP)
        assert info.pan_speed == pytest.approx(round(2.5 / STEP) * STEP) and not info.halt
        moved = len(observer.events['PTU'])
        observer.until(lambda o: len(o.events['PTU']) > moved and latest(o).moving, 'moving')
        observer.until(lambda o: not latest(o).moving, 'the move ends', timeout=10)
        data = latest(observer)
        assert (unit.pan, unit.tilt) == (3090, round(-0.3 / STEP))        # the unit itself
        assert (data.pan, data.tilt) == pytest.approx((3090 * STEP, round(-0.3 / STEP) * STEP))
        assert (data.pan_velocity, data.tilt_velocity) == (0.0, 0.0)
        # Velocity mode: the signed speed drives the pan; halt stops it where it is.
        observer.request('PTU', velocity_mode=True, pan_speed=-0.5)
        observer.until(lambda o: latest(o).pan_velocity == pytest.approx(-0.5, abs=0.05),
                       'pan at -0.5 rad/s')
        assert observer.infos['PTU'].velocity_mode and latest(observer).moving
        assert observer.infos['PTU'].pan_speed == pytest.approx(round(-0.5 / STEP) * STEP)
        observer.request('PTU', halt=True)
        observer.until(lambda o: o.infos['PTU'].halt and not latest(o).moving, 'halted')
        stopped = unit.pan
        assert stopped < 3090 and observer.infos['PTU'].pan_speed == 0.0
        observer.until(lambda o: len(o.events['PTU']) >= moved + 30, 'more readings')
        assert unit.pan == stopped and latest(observer).pan == pytest.approx(stopped * STEP)
        # Readings at the configured 10 Hz, stamped with wall-clock time.
        assert median_interval(observer.stamps('PTU')) == pytest.approx(0.1, abs=0.02)
        assert abs(observer.stamps('PTU')[-1] - time.time()) < 5.0
        assert 'Traceback' not in child.stderr


def test_a_silent_unit_is_logged_and_nothing_is_published_until_it_is_back(
        unit: Ptu46Emulator, observer: Observer, tmp_path: pathlib.Path) -> None:
    with ptu_server(ptu_config(tmp_path, unit.path)) as child:
        observer.until(lambda o: len(o.events['PTU']) >= 5, 'readings before the silence')
        unit.silent.set()
        observer.until(lambda o: 'is silent' in child.stderr, 'the silence logged', timeout=10)
        # Every reading read before the silence was stamped before it was logged; the module
        # keeps polling the silent unit for a few loop turns, in which it must publish nothing.
        quiet = observer.quiet_span('PTU', 'loop turns while silent')
        asked = unit.bytes_in
        observer.until(lambda o: unit.bytes_in > asked, 'a poll of the silent unit', timeout=10)
        # It comes back power-cycled (at 0); the commanded pan is sent again.
        unit.replug(power_cycle=True)
        unit.silent.clear()
        observer.request('PTU', pan=0.2)     # dropped or applied: either way the unit ends there
        back = time.time()
        observer.until(lambda o: 'is back' in child.stderr and sum(
            s > back for s in o.stamps('PTU')) >= 5, 'readings again', timeout=10)
        observer.request('PTU', pan=0.2)
        observer.until(lambda o: latest(o).pan == pytest.approx(0.2, abs=STEP) and not latest(o).moving,
                       'the unit moves again after its return', timeout=10)
        assert logged(child, 'WARN', 'is silent') == 1              # once each
        assert logged(child, 'NOTICE', 'is back') == 1
    # Readings from after the silence arrived, so all before them did: none is of the silence.
    assert_none_between(observer.stamps('PTU'), quiet, back, 'PTU readings while silent')


@pytest.mark.parametrize(('device', 'name', 'reason'), [
    ('<device port="/dev/null" name="PTU" baud="115200"/>', 'PTU', ':3: attribute baud'),
    ('<device port="/dev/null" name="PTU"/>', 'OtherPTU', ': no <device> named "OtherPTU"'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                     device: str, name: str, reason: str) -> None:
    path = ptu_config(tmp_path, '', device=device)
    with ptu_server(path, name) as child:
        assert child.process.wait(timeout=30) == 2
    assert f'ptu_server: {path}{reason}' in child.stderr


def test_the_shipped_config_runs_server_and_emulator_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    link = str(tmp_path / 'ttyPTU')
    for name in ('ptu-config.xml', 'mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_text((CONFIG / name).read_text().replace('/tmp/wurde-ptu', link))
    assert link in (tmp_path / 'mcp-config.xml').read_text()
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: 'PTU' in o.infos and len(o.events['PTU']) >= 3, 'PTU data',
                       timeout=30)
        observer.request('PTU', pan=-0.4, tilt=0.2)
        observer.until(lambda o: (latest(o).pan, latest(o).tilt) == pytest.approx((-0.4, 0.2), abs=STEP)
                       and not latest(o).moving, 'the unit at the requested angles', timeout=15)
        mcp.stop(timeout=30)
    for module in ('PTUEmulator', 'PTU'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        # A slow exit: the MCP's timing lines and the module's traceback dump say where it hung.
        assert log.rstrip().endswith('--- exit code 0'), f'{log[-4000:]}\nMCP: {(mcp.stdout + mcp.stderr)[-3000:]}'
