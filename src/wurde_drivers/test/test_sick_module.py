"""sick_server (WURDE 7.5, Pluto 8.1) against the SICK emulator over a real pty, as real processes.

The emulator runs in the test process (a thread on a pty) where a test must control it (values,
silence, a fatal error); the last test runs the shipped config/sick under the MCP.
"""

from __future__ import annotations

import math
import os
import pathlib
import re
import time
from collections.abc import Callable, Iterator, Sequence

import pytest
import serial
from sim_fixture import Observer
from wurde_testing import ChildProcess, find_executable
from wurde_testing.parameters import ParameterTool

from wurde_drivers.sick import codec as sick
from wurde_drivers.sick.config import LaserDevice
from wurde_drivers.sick.emulator import SickEmulator
from wurde_drivers.sick.emulator_module import DEFAULT_ROOM, room_source
from wurde_drivers.sick.module import LOG_NAME, log_line, make_laser, scan_period

ROOT = pathlib.Path(__file__).resolve().parents[3]
SHIPPED = ROOT / 'config' / 'sick'
STREAMS = {'laser': 'RangeFinder', 'laser/RWI': 'RangeFinder', 'laser/Timing': 'FVectorState'}
INF_BEAM, NAN_BEAM = 40, 41
#: Centre of the sweep to the last byte read: 361 values at 38400 baud, half a 1/75 s sweep.
DELAY_S = sick.telegram_size(361) * 10 / 38400 + 0.5 / 75


def source(count: int, fov_deg: float) -> list[float]:
    """0.5 m rising to 6.5 m across the scan (asymmetric), one beam too far, one invalid."""
    ranges = [0.5 + 6.0 * i / (count - 1) for i in range(count)]
    ranges[INF_BEAM], ranges[NAN_BEAM] = math.inf, math.nan
    return ranges


def assert_ranges(got: Sequence[float], want: Sequence[float], step: float = 0.01) -> None:
    assert len(got) == len(want)
    for index, (g, w) in enumerate(zip(got, want)):
        if math.isnan(w):
            assert math.isnan(g), index
        elif math.isinf(w):
            assert g == math.inf, index
        else:
            assert abs(g - w) <= step / 2 + 1e-6, (index, g, w)


def write_config(directory: pathlib.Path, port: str, **attributes: str) -> pathlib.Path:
    extra = ''.join(f' {key}="{value}"' for key, value in attributes.items())
    path = directory / 'laser-config.xml'
    path.write_text(f'<laser-config>\n  <device port="{port}" name="laser"{extra}/>\n</laser-config>\n')
    return path


def server(config: pathlib.Path, **env: str) -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'sick_server'), '-c', str(config),
                         '-n', 'laser'], env=dict(os.environ, **env))


def nearest(events: Sequence[tuple[float, object]], stamp: float, within: float = 2e-6) -> object:
    """The event stamped ``stamp`` (to ``within`` s), or None."""
    hits = [event for when, event in events if abs(when - stamp) <= within]
    return hits[0] if hits else None


def _heard_everywhere(observer: Observer) -> list[float]:
    """Stamps of the scans heard on the main stream, its RWI copy and its timing."""
    return [stamp for stamp, _ in observer.events['laser']
            if nearest(observer.events['laser/RWI'], stamp + DELAY_S) is not None
            and nearest(observer.events['laser/Timing'], stamp) is not None]


def is_fatal(scan: object) -> bool:
    return all(r == -1.0 for r in scan.ranges)  # type: ignore[attr-defined]


def test_log_line_format_and_scan_period_and_room() -> None:
    assert log_line(1700000000.5, [1.2, math.inf, math.nan, 0.0123]) == \
        '1700000000.500000 : 1.200 inf nan 0.012\n'
    # Pluto 8.1's defaults (361 values, 38400 baud) give a scan every 190.625 ms, the dummy's rate
    assert scan_period(LaserDevice(port='p', name='n', type='LMS')) == pytest.approx(0.190625)
    assert scan_period(LaserDevice(port='p', name='n', type='LMS', resolution=1.0,
                                   baud=500000)) == pytest.approx(1 / 75)
    room = room_source(1.2, 4.5, 2.5)(361, 180.0)
    assert (room[0], room[180], room[360]) == pytest.approx((1.2, 4.5, 2.5))
    assert room[90] == pytest.approx(1.2 / math.sin(math.radians(45)))   # the right wall at -45°


def test_the_line_parity_is_the_configured_one() -> None:
    """No guessing from the port's path: a PLS gets even parity unless its config says none."""
    for kind, parity, expected in (('PLS', '', serial.PARITY_EVEN), ('LMS', '', serial.PARITY_NONE),
                                   ('PLS', 'none', serial.PARITY_NONE),
                                   ('LMS', 'even', serial.PARITY_EVEN)):
        laser = make_laser(LaserDevice(port='/dev/pts/0', name='n', type=kind, parity=parity))
        assert laser.parity == expected, (kind, parity)


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer(STREAMS)
    try:
        yield watcher
    finally:
        watcher.close()


def test_scans_carry_the_emulators_values_on_every_stream_and_are_logged(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    data = tmp_path / 'data'
    with SickEmulator(scan_source=source) as emulator:
        config = write_config(tmp_path, emulator.path, type='LMS', log='true')
        with server(config, WURDE_DATA_DIR=str(data)) as child:
            # Each stream's subscription matches in its own time: four scans heard on all three.
            observer.until(lambda o: len(_heard_everywhere(o)) >= 4 and 'laser' in o.infos,
                           'four scans on every stream', timeout=30)
            assert child.stop() == 0, child.stderr
        assert emulator.error is None
    main = observer.events['laser']
    heard = _heard_everywhere(observer)
    for stamp, scan in main:
        assert_ranges(scan.ranges, source(361, 180.0))
        # the RWI copy of the same scan: every other beam, stamped at its arrival (Pluto 8.1);
        # every scan between the first and last heard on all streams has its copy
        twin = nearest(observer.events['laser/RWI'], stamp + DELAY_S)
        if min(heard) <= stamp <= max(heard):
            assert twin is not None, stamp
        if twin is not None:
            assert_ranges(twin.ranges, source(361, 180.0)[::2])
    assert [list(m.element) for _, m in observer.events['laser/Timing']] == [[361]] * len(
        observer.events['laser/Timing'])
    assert {s for s, _ in observer.events['laser/Timing']} >= {s for s, _ in main if min(heard) <= s <= max(heard)}
    assert observer.infos['laser'].max_range == pytest.approx(81.82)
    # LaserLog.txt: "stamp : ranges", stamp with 6 decimals, metres with 3, one line per scan.
    lines = (data / LOG_NAME).read_text().splitlines()
    number = r'(?:\d+\.\d{3}|inf|nan)'
    logged = []
    for line in lines:
        assert re.fullmatch(rf'\d+\.\d{{6}} : {number}(?: {number}){{360}}', line), line[:80]
        stamp, _, readings = line.partition(' : ')
        logged.append((float(stamp), [float(r) for r in readings.split()]))
    assert len(lines) >= len(main)
    for stamp, scan in main:
        line = nearest(logged, stamp)
        assert line is not None, stamp
        assert_ranges(line, scan.ranges, step=0.002)


def test_invert_and_log_are_tunables_taken_at_the_next_scan(observer: Observer,
                                                           tmp_path: pathlib.Path) -> None:
    """``ros2 param set /laser invert true`` reverses the beams from the next scan on; ``log``
    switches LaserLog.txt on and off while the module runs."""
    data = tmp_path / 'data'
    want = source(361, 180.0)

    def scans_after(count: int) -> Callable[[Observer], bool]:
        return lambda o: len(o.events['laser']) >= count

    with SickEmulator(scan_source=source) as emulator:
        config = write_config(tmp_path, emulator.path, type='LMS')
        with server(config, WURDE_DATA_DIR=str(data)) as child:
            observer.until(lambda o: len(o.events['laser']) >= 2, 'scans', timeout=30)
            assert_ranges(observer.events['laser'][-1][1].ranges, want)
            tool = ParameterTool('/laser')
            try:
                assert tool.get('invert', 'log') == [False, False]
                assert tool.set('invert', True) == (True, '')
                changed = time.time()       # a scan centred later was read after the change
                observer.until(lambda o: sum(t > changed for t in o.stamps('laser')) >= 2,
                               'scans after the change')
                for stamp, scan in observer.events['laser']:
                    if stamp > changed:
                        assert_ranges(scan.ranges, want[::-1])
                assert not (data / LOG_NAME).exists()
                assert tool.set('log', True) == (True, '')
                observer.until(lambda o: (data / LOG_NAME).exists()
                               and len((data / LOG_NAME).read_text().splitlines()) >= 3, 'lines logged')
                assert tool.set('log', False) == (True, '')
                lines = (data / LOG_NAME).read_text().splitlines()
                observer.until(scans_after(len(observer.events['laser']) + 3), 'scans after logging ends')
                assert (data / LOG_NAME).read_text().splitlines() == lines
            finally:
                tool.close()
            assert child.stop() == 0, child.stderr
        assert emulator.error is None
    for line in lines:
        stamp, _, readings = line.partition(' : ')
        assert_ranges([float(r) for r in readings.split()], want[::-1], step=0.012)  # cm and 3 decimals


def test_a_silent_laser_is_logged_and_publishes_nothing_until_it_is_back(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    with SickEmulator(scan_source=source) as emulator:
        with server(write_config(tmp_path, emulator.path, type='LMS')) as child:
            observer.until(lambda o: len(o.events['laser']) >= 2, 'scans', timeout=30)
            emulator.silent.set()
            went_silent = time.time()
            observer.until(lambda o: 'is silent' in child.stderr, 'the silence logged', timeout=10)
            seen = {stream: len(events) for stream, events in observer.events.items()}
            logged = time.time()
            observer.until(lambda o: time.time() > logged + 0.4, 'an observation window')
            assert {stream: len(events) for stream, events in observer.events.items()} == seen
            emulator.silent.clear()
            back = time.time()
            observer.until(lambda o: len(o.events['laser']) > seen['laser'] + 1
                           and 'is back' in child.stderr, 'scans again', timeout=10)
            assert child.stop() == 0
    for stamp, scan in observer.events['laser']:
        assert not went_silent < stamp < back - DELAY_S - 0.05, stamp   # nothing while silent
        assert_ranges(scan.ranges, source(361, 180.0))                  # never -1
    warnings = [line for line in child.stderr.splitlines() if line.startswith('[WARN] laser:')]
    assert len([line for line in warnings if 'is silent' in line]) == 1, warnings   # logged once
    assert 'resetting' not in child.stderr


def test_a_fatal_error_gives_minus_one_ranges_then_real_scans_again(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    expected = source(361, 180.0)[::-1]           # an upside-down PLS: robot order reversed
    with SickEmulator(kind='PLS', scan_source=source, reset_s=1.0) as emulator:
        # the emulator's pty cannot carry the PLS's even parity: the config says so
        config = write_config(tmp_path, emulator.path, type='PLS', invert='true', parity='none')
        with server(config) as child:
            observer.until(lambda o: len(o.events['laser']) >= 2, 'scans', timeout=30)
            emulator.fatal_error()

            def recovered(o: Observer) -> bool:
                scans = [m for _, m in o.events['laser']]
                fatal = [i for i, m in enumerate(scans) if is_fatal(m)]
                return bool(fatal) and len(scans) - fatal[-1] > 2
            observer.until(recovered, '-1 ranges, then scans again', timeout=30)
            assert child.stop() == 0
        assert 0x10 in emulator.commands and not emulator.fatal   # the module reset the laser
    scans = [m for _, m in observer.events['laser']]
    fatal = [i for i, m in enumerate(scans) if is_fatal(m)]
    assert fatal == list(range(fatal[0], fatal[-1] + 1)) and fatal[0] >= 2   # one run, between
    for index, scan in enumerate(scans):
        if index not in fatal:
            assert_ranges(scan.ranges, expected)
    rwi_fatal = [m for _, m in observer.events['laser/RWI'] if is_fatal(m)]
    assert rwi_fatal and all(len(m.ranges) == 181 for m in rwi_fatal)
    assert len(scans[fatal[0]].ranges) == 361
    for text in ('is silent', 'rebooting after a fatal error', 'reset and streaming again'):
        assert text in child.stderr, child.stderr


@pytest.mark.parametrize(('body', 'where', 'reason'), [
    ('<laser-config>\n  <device port="p" name="laser" type="LMX"/>\n</laser-config>\n', ':2:',
     'type="LMX"'),
    ('<laser-config>\n  <device port="p" name="front" type="LMS"/>\n</laser-config>\n', ':',
     'no <device> named "laser" (devices: front)'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                    body: str, where: str, reason: str) -> None:
    path = tmp_path / 'laser-config.xml'
    path.write_text(body)
    with server(path) as child:
        assert child.process.wait(timeout=30) == 2
        child.stop()
    assert f'sick_server: {path}{where}' in child.stderr and reason in child.stderr


def test_the_shipped_config_runs_driver_and_emulator_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    link = tmp_path / 'ttySICK'
    for name in ('mcp-config.xml', 'mcp-mappings.xml', 'laser-config.xml'):
        text = (SHIPPED / name).read_text()
        (tmp_path / name).write_text(text.replace('/tmp/wurde-sick', str(link)))
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        try:
            observer.until(lambda o: link.is_symlink(), 'the emulator linked at its port', timeout=20)
        except AssertionError as error:
            emulator_log = tmp_path / 'mcp-modules' / 'SICKEmulator.log'
            raise AssertionError(f'{error}\n{emulator_log.read_text()[-1500:]}') from None
        observer.until(lambda o: len(o.events['laser']) >= 3, 'scans from the MCP run', timeout=30)
        mcp.stop(timeout=30)
    room = room_source(*DEFAULT_ROOM)(361, 180.0)
    for _, scan in observer.events['laser']:
        assert_ranges(scan.ranges, room)
    for module in ('SICKEmulator', 'laser'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), log[-2000:]
