"""dmu_module end to end: the driver module as a real process against the DMU emulator on a pty.

The emulator runs in the test process (so the test controls its motion and its silence); the
module is a child process with ``-c`` a dmu-config in tmp naming the emulator's pty. The last test
brings up the shipped config/dmu (emulator program and module) under the MCP.
"""

from __future__ import annotations

import math
import os
import pathlib
import time
from collections.abc import Iterator

import pytest
from sim_fixture import Observer, assert_none_between, heartbeat
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.dmu.codec import G
from wurde_drivers.dmu.emulator import DmuEmulator, constant_rate

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'dmu'
STREAMS = {'PlutoDMU': 'DMUState', 'PlutoDMU/Raw': 'DMUState'}
YAW = 0.2            # rad/s about the robot's z (up)
CUTOFF = 4.0         # Hz


def dmu_config(directory: pathlib.Path, port: str, *, device: str | None = None) -> pathlib.Path:
    path = directory / 'dmu-config.xml'
    device = device or f'<device port="{port}" name="PlutoDMU" cutoff="{CUTOFF}"/>'
    path.write_text(f'<?xml version="1.0"?>\n<dmu-config>\n  {device}\n</dmu-config>\n')
    return path


def dmu_module(config: pathlib.Path, name: str = 'PlutoDMU') -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'dmu_module'), '-c', str(config), '-n', name])


def logged(child: ChildProcess, prefix: str, text: str) -> int:
    """Lines of the module's own Logger (not the /rosout echo) that contain ``text``."""
    return sum(line.startswith(prefix) and text in line for line in child.stderr.splitlines())


@pytest.fixture
def emulator() -> Iterator[DmuEmulator]:
    with DmuEmulator(motion_source=constant_rate(-YAW), rate_hz=100.0) as device:   # z down
        yield device
    assert device.error is None


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({**STREAMS, **heartbeat('PlutoDMU')})
    try:
        yield watcher
    finally:
        watcher.close()


def test_samples_flow_raw_and_filtered_with_the_emulated_motion(
        emulator: DmuEmulator, observer: Observer, tmp_path: pathlib.Path) -> None:
    with dmu_module(dmu_config(tmp_path, emulator.path)) as child:
        observer.until(lambda o: all(len(o.events[s]) >= 60 for s in STREAMS), '60 samples on both')
        assert 'streaming (angle mode, 38400 baud' in child.stderr
    raw = [m for _, m in observer.events['PlutoDMU/Raw']]
    for m in raw:   # robot frame, z up: the turn is +YAW about z, gravity reads +g
        assert (m.theta, m.phi, m.psi, m.rate_x, m.rate_y) == pytest.approx((0, 0, 0, 0, 0), abs=1e-3)
        assert (m.rate_z, m.accel_x, m.accel_y, m.accel_z) == pytest.approx((YAW, 0, 0, G), abs=2e-3)
    raw_stamps = observer.stamps('PlutoDMU/Raw')
    assert abs(raw_stamps[-1] - time.time()) < 5.0                 # wall-clock stamps
    delay = 1.0 / (2 * math.pi * CUTOFF)
    assert observer.infos['PlutoDMU'].filtered and not observer.infos['PlutoDMU/Raw'].filtered
    assert observer.infos['PlutoDMU'].cutoff_frequency == CUTOFF
    assert observer.infos['PlutoDMU'].filter_delay == pytest.approx(delay)
    # Each filtered sample is a raw one stamped earlier by the filter delay (within the raw ones
    # received: the two topics are discovered separately, and the newest raw may be on its way).
    filtered = observer.events['PlutoDMU']
    paired = [s for s, _ in filtered if raw_stamps[0] - 1e-6 <= s + delay <= raw_stamps[-1] + 1e-6]
    assert len(paired) >= 50
    assert all(min(abs(r - s - delay) for r in raw_stamps) < 2e-6 for s in paired)
    # The heading integrates the (constant) z rate: YAW times the time between the samples.
    (s0, first), (s1, last) = filtered[0], filtered[-1]
    assert s1 - s0 > 0.4
    # (abs: an epoch stamp as a float64 resolves only ~0.2 us)
    assert last.theta - first.theta == pytest.approx(last.rate_z * (s1 - s0), abs=1e-5)
    assert last.rate_z == pytest.approx(YAW, abs=1e-3) and last.accel_z == pytest.approx(G, abs=2e-3)


def test_a_silent_unit_is_logged_and_nothing_is_published_until_it_is_back(
        emulator: DmuEmulator, observer: Observer, tmp_path: pathlib.Path) -> None:
    with dmu_module(dmu_config(tmp_path, emulator.path)) as child:
        observer.until(lambda o: len(o.events['PlutoDMU/Raw']) >= 10, 'samples before the silence')
        emulator.silent.set()
        observer.until(lambda o: 'is silent' in child.stderr, 'the silence logged', timeout=10)
        # Every sample read before the silence was published before it was logged; the module
        # runs a few loop turns while the unit is silent, in which it must publish nothing.
        quiet = observer.quiet_span('PlutoDMU', 'loop turns while silent')
        emulator.silent.clear()
        back = time.time()
        observer.until(lambda o: 'is back' in child.stderr and sum(
            s > back for s in o.stamps('PlutoDMU/Raw')) >= 10, 'samples again', timeout=10)
        assert logged(child, '[WARN] PlutoDMU:', 'is silent') == 1               # once each
        assert logged(child, '[NOTICE] PlutoDMU:', 'is back') == 1
        assert sum(s > back for s in observer.stamps('PlutoDMU')) > 0
    # Samples from after the silence arrived, so all before them did: none is of the silence
    # (the filtered stream's stamps are earlier by the filter's delay, which its info gives).
    delay = observer.infos['PlutoDMU'].filter_delay
    assert_none_between(observer.stamps('PlutoDMU/Raw'), quiet, back, 'raw samples while silent')
    assert_none_between(observer.stamps('PlutoDMU'), quiet, back - delay,
                        'filtered samples while silent')


@pytest.mark.parametrize(('device', 'name', 'reason'), [
    ('<device port="/dev/null" name="PlutoDMU" mode="voltage"/>', 'PlutoDMU', ':3: attribute mode'),
    ('<device port="/dev/null" name="PlutoDMU"/>', 'OtherDMU', ': no <device> named "OtherDMU"'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                     device: str, name: str, reason: str) -> None:
    path = dmu_config(tmp_path, '', device=device)
    with dmu_module(path, name) as child:
        assert child.process.wait(timeout=30) == 2
    assert f'dmu_module: {path}{reason}' in child.stderr


def test_the_shipped_config_runs_driver_and_emulator_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    link = str(tmp_path / 'ttyDMU')
    for name in ('dmu-config.xml', 'mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_text((CONFIG / name).read_text().replace('/tmp/wurde-dmu', link))
    assert link in (tmp_path / 'mcp-config.xml').read_text()
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: all(len(o.events[s]) >= 20 for s in STREAMS), 'DMU data', timeout=30)
        _, raw = observer.events['PlutoDMU/Raw'][-1]
        assert (raw.rate_z, raw.accel_z) == pytest.approx((0.1, G), abs=2e-3)   # the shipped -w 0.1
        assert observer.events['PlutoDMU'][-1][1].theta > 0
        mcp.stop(timeout=30)
    for module in ('DMUEmulator', 'PlutoDMU'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), log[-2000:]
