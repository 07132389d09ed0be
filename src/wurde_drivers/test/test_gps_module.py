"""gps_module end to end: Pluto's GPS module as a real process against the emulated receiver.

The emulator runs in the test process (so the test knows the true positions and controls its
silence); the module is a child process with ``-c`` a gps-config in tmp naming the emulator's
pty. The last test brings up the shipped config/gps (emulator program and module) under the MCP.
"""

from __future__ import annotations

import datetime
import math
import os
import pathlib
import time
from collections.abc import Iterator

import pytest
from sim_fixture import Observer, median_interval
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.gps.emulator import GpsEmulator
from wurde_drivers.gps.emulator_module import circle
from wurde_drivers.gps.geo import LocalFrame

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'gps'
CENTRE = (48.1500, 11.5800)
RADIUS = 15.0         # m
LAP = 20.0            # s: fixes 10 Hz apart are about 0.5 m apart
RATE = 10.0           # Hz


def gps_config(directory: pathlib.Path, port: str, *, device: str | None = None) -> pathlib.Path:
    path = directory / 'gps-config.xml'
    device = device or f'<device port="{port}" name="PlutoGPS" timeout="1"/>'
    path.write_text(f'<?xml version="1.0"?>\n<gps-config>\n  {device}\n</gps-config>\n')
    return path


def gps_module(config: pathlib.Path, name: str = 'PlutoGPS') -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'gps_module'), '-c', str(config),
                         '-n', name])


def logged(child: ChildProcess, level: str, text: str) -> int:
    """Lines of the module's own Logger (not the /rosout echo) that contain ``text``."""
    return sum(line.startswith(f'[{level}] PlutoGPS:') and text in line
               for line in child.stderr.splitlines())


@pytest.fixture
def receiver() -> Iterator[GpsEmulator]:
    with GpsEmulator(circle(*CENTRE, RADIUS, LAP), rate_hz=RATE, quality=2,
                     satellites=9) as emulator:
        yield emulator
    assert emulator.error is None


class RecordingClock:
    """The emulator's UTC clock, keeping every time it gave: one per GGA/RMC pair it built."""

    def __init__(self) -> None:
        self.given: list[datetime.datetime] = []

    def __call__(self) -> datetime.datetime:
        now = datetime.datetime.now(datetime.timezone.utc)
        self.given.append(now)
        return now

    def times_of_day(self) -> set[int]:
        """The GGA times sent, in hundredths of a second since midnight (as the GGA has them)."""
        return {(t.hour * 3600 + t.minute * 60 + t.second) * 100 + t.microsecond // 10000
                for t in list(self.given)}


def _twins(observer: Observer) -> set[float]:
    """Stamps of the fixes heard in both layouts."""
    return ({stamp for stamp, _ in observer.events['PlutoGPS']}
            & {stamp for stamp, _ in observer.events['PlutoGPS/Pluto']})


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({'PlutoGPS': 'GPS', 'PlutoGPS/Pluto': 'ActuatorState'})
    try:
        yield watcher
    finally:
        watcher.close()


def test_fixes_flow_on_the_grid_of_the_first_good_fix(receiver: GpsEmulator, observer: Observer,
                                                       tmp_path: pathlib.Path) -> None:
    with gps_module(gps_config(tmp_path, receiver.path)) as child:
        # Each layout's subscription matches in its own time: count the fixes seen in both.
        observer.until(lambda o: 'PlutoGPS' in o.infos and len(_twins(o)) >= 30, '30 fixes in both layouts')
        assert 'grid origin (first good fix)' in child.stderr
    info = observer.infos['PlutoGPS']
    assert (info.min_satellites, info.min_quality) == (6, 2)        # Pluto 8.4's defaults
    fixes = [m for _, m in observer.events['PlutoGPS']]
    # The origin was a fix (the first good one, which the observer may have missed): it lies on
    # the emulated circle round CENTRE, as every fix does, and x, y are on its grid.
    frame = LocalFrame(info.origin_latitude, info.origin_longitude, 30.0)
    cx, cy = frame.to_xy(*CENTRE)
    assert math.hypot(cx, cy) == pytest.approx(RADIUS, abs=0.05)
    for fix in fixes:
        assert (fix.x, fix.y) == pytest.approx(frame.to_xy(fix.latitude, fix.longitude), abs=1e-3)
        assert math.hypot(fix.x - cx, fix.y - cy) == pytest.approx(RADIUS, abs=0.05)
        assert (fix.satellites, fix.quality, fix.hdop) == (9, 2, pytest.approx(0.9))
        assert fix.altitude == pytest.approx(30.0)
        assert 0.0 <= fix.fix_time < 86400.0
    # The receiver moves: along the circle at RADIUS * 2 pi / LAP m/s, fix after fix.
    steps = [math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(fixes, fixes[1:])]
    speed = RADIUS * 2.0 * math.pi / LAP
    assert sorted(steps)[len(steps) // 2] == pytest.approx(speed / RATE, abs=0.05)
    stamps = observer.stamps('PlutoGPS')
    assert median_interval(stamps) == pytest.approx(1.0 / RATE, abs=0.02)
    assert abs(stamps[-1] - time.time()) < 5.0                   # wall-clock stamps
    # Pluto 8.4's layout of the same fixes: force[0] satellites, force[3] quality, position the
    # grid's x, y (float32), one event per fix with the fix's stamp.
    by_stamp = dict(observer.events['PlutoGPS'])
    pluto = observer.events['PlutoGPS/Pluto']
    # Once both are heard, every fix comes in both layouts: no event without its twin in between
    # (the newest may be taken in one layout before the other).
    first, last = min(_twins(observer)), max(_twins(observer))
    assert {s for s, _ in pluto if first <= s <= last} == {s for s in by_stamp if first <= s <= last}
    for stamp, state in pluto:
        if stamp not in by_stamp:
            continue                      # its GPS twin came before the observer was listening
        fix = by_stamp[stamp]
        assert state.cmd_flags == 0 and list(state.velocity) == [] == list(state.acceleration)
        assert list(state.force) == pytest.approx([9.0, 0.9, 30.0, 2.0])
        assert (state.force[0], state.force[3]) == (fix.satellites, fix.quality)
        assert list(state.position) == pytest.approx([fix.x, fix.y], abs=1e-4)


def test_a_silent_receiver_is_logged_and_nothing_is_published_until_it_is_back(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """Nothing is published while the receiver is silent, proven by what comes after: every fix
    published, before and after the silence, is one GGA the receiver sent (its UTC time is one
    the emulator's clock gave), each once — a fix made up while silent (a repeat,
    a NaN, a stale position) would break that — and fixes after the silence did arrive."""
    clock = RecordingClock()
    observer = Observer({'PlutoGPS': 'GPS'})
    try:
        with GpsEmulator(circle(*CENTRE, RADIUS, LAP), rate_hz=RATE, quality=2, satellites=9,
                         clock=clock) as receiver, \
                gps_module(gps_config(tmp_path, receiver.path)) as child:
            observer.until(lambda o: len(o.events['PlutoGPS']) >= 5, 'fixes before the silence')
            receiver.silent.set()
            observer.until(lambda o: 'is silent' in child.stderr, 'the silence logged',
                           timeout=10)
            before = len(observer.events['PlutoGPS'])
            receiver.silent.clear()
            observer.until(lambda o: 'is back' in child.stderr
                           and len(o.events['PlutoGPS']) >= before + 5, 'fixes again',
                           timeout=10)
            assert logged(child, 'WARN', 'is silent') == 1              # once each
            assert logged(child, 'NOTICE', 'is back') == 1
        assert receiver.error is None
    finally:
        observer.close()
    sent = clock.times_of_day()
    published = [round(fix.fix_time * 100) for _, fix in observer.events['PlutoGPS']]
    assert all(when in sent for when in published), 'a fix the receiver never sent'
    assert len(set(published)) == len(published), 'a fix published twice'


@pytest.mark.parametrize(('device', 'name', 'reason'), [
    ('<device port="/dev/null" name="PlutoGPS" origin-latitude="59"/>', 'PlutoGPS',
     ':3: <device> needs both origin-latitude and origin-longitude'),
    ('<device port="/dev/null" name="PlutoGPS"/>', 'OtherGPS', ': no <device> named "OtherGPS"'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                     device: str, name: str, reason: str) -> None:
    path = gps_config(tmp_path, '', device=device)
    with gps_module(path, name) as child:
        assert child.process.wait(timeout=30) == 2
    assert f'gps_module: {path}{reason}' in child.stderr


def test_the_shipped_config_runs_module_and_emulator_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    link = str(tmp_path / 'ttyGPS')
    for name in ('gps-config.xml', 'mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_text((CONFIG / name).read_text().replace('/tmp/wurde-gps', link))
    assert link in (tmp_path / 'mcp-config.xml').read_text()
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: 'PlutoGPS' in o.infos and len(o.events['PlutoGPS']) >= 3,
                       'GPS fixes', timeout=30)
        mcp.stop(timeout=30)
    info = observer.infos['PlutoGPS']
    assert (info.origin_latitude, info.origin_longitude) == (59.3498, 18.0707)   # configured
    fixes = [m for _, m in observer.events['PlutoGPS']]
    # The shipped emulator circles the configured origin at 20 m, one lap in 120 s.
    assert all(math.hypot(f.x, f.y) == pytest.approx(20.0, abs=0.05) for f in fixes)
    assert all((f.satellites, f.quality) == (8, 2) for f in fixes)
    assert fixes[0].x != fixes[-1].x or fixes[0].y != fixes[-1].y
    for module in ('GPSEmulator', 'PlutoGPS'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), log[-2000:]
