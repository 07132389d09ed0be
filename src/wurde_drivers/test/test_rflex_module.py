"""rflex_server end to end: the driver module as a real process against the rFLEX emulator on a pty.

The emulator runs in the test process (so the test presses its bumpers, silences it and reads what
it was told); the module is a child process with ``-c`` an rflex-config in tmp naming the
emulator's pty. The last test brings up the shipped config/rflex (emulator program and module)
under the MCP.
"""

from __future__ import annotations

import math
import os
import pathlib
import struct
import time
from collections.abc import Iterator

import pytest
from sim_fixture import Observer, assert_none_between, heartbeat
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.rflex.codec import Mot, Port
from wurde_drivers.rflex.emulator import RFlexEmulator
from wurde_drivers.rflex.robots import ATRV2, ATRV_JR, B21IR, B21R, RobotParams

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'rflex'
#: One range per B21r sonar (m); sonar 5 has no echo. Kept below 4.6 m, where the emulator
#: would move a raw range off a 0x1B high byte.
RANGES = [math.inf if i == 5 else 0.5 + 0.08 * i for i in range(len(B21R.sonars))]
VOLTS = 25.5


def streams(name: str, drive: str) -> dict[str, str]:
    return {f'{name}Drive': drive, f'{name}Motion': 'Egomotion', f'{name}Sonar': 'RangeFinder',
            f'{name}Bumpers': 'Bumper', f'{name}Power': 'Power'}


def rflex_config(directory: pathlib.Path, port: str, *, device: str | None = None) -> pathlib.Path:
    path = directory / 'rflex-config.xml'
    device = device or f'<device port="{port}" name="base" type="B21r"/>'
    path.write_text(f'<?xml version="1.0"?>\n<rflex-config>\n  {device}\n</rflex-config>\n')
    return path


def rflex_server(config: pathlib.Path, name: str = 'base') -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'rflex_server'), '-c', str(config),
                         '-n', name])


def logged(child: ChildProcess, prefix: str, text: str) -> int:
    """Lines of the module's own Logger (not the /rosout echo) that contain ``text``."""
    return sum(line.startswith(prefix) and text in line for line in child.stderr.splitlines())


def set_dirs(emulator: RFlexEmulator, axis: int) -> list[int]:
    """The signed velocities (counts/s) of every SET_DIR the driver sent for ``axis``."""
    result = []
    for packet in emulator.commands():
        if (packet.port, packet.opcode) == (Port.MOT, Mot.SET_DIR):
            ax, vel, _, _, direction = struct.unpack('>BIIIB', packet.data[:14])
            if ax == axis:
                result.append(vel if direction else -vel)
    return result


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({**streams('base', 'SynchroDrive'), **heartbeat('base')})
    try:
        yield watcher
    finally:
        watcher.close()


def emulated(robot: RobotParams = B21R) -> RFlexEmulator:
    return RFlexEmulator(robot, voltage=VOLTS, sonar_ranges=lambda: RANGES)


def test_sensor_data_flows_with_the_emulated_values_and_the_brake_stays_set(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    with emulated() as emulator, rflex_server(rflex_config(tmp_path, emulator.path)) as child:
        observer.until(lambda o: all(len(e) >= 3 for s, e in o.events.items() if s != 'baseDrive')
                       and o.infos.get('baseDrive') is not None and o.infos['baseDrive'].brake,
                       'data on every stream, the brake reported set', timeout=20)
        _, sonar = observer.events['baseSonar'][-1]
        expected = [min(r, 10.0) for r in RANGES]            # no echo reads as the max range
        assert list(sonar.ranges) == pytest.approx(expected, abs=2e-3)
        info = observer.infos['baseSonar']
        assert not info.uniform and info.max_range == 10.0
        first = info.sensor_positions[0]
        assert (first.x, first.y, first.theta) == pytest.approx(
            (B21R.sonars[0].x, B21R.sonars[0].y, B21R.sonars[0].yaw))
        assert len(info.sensor_positions) == 48
        _, power = observer.events['basePower'][-1]
        assert power.voltage == pytest.approx(VOLTS, abs=0.01) and not power.low
        assert observer.infos['basePower'].nominal_voltage == 24.0
        _, motion = observer.events['baseMotion'][-1]
        assert (motion.location.x, motion.location.y, motion.tv) == (0.0, 0.0, 0.0)
        gaps = [b - a for a, b in zip(observer.stamps('baseMotion'), observer.stamps('baseMotion')[1:])]
        assert sorted(gaps)[len(gaps) // 2] == pytest.approx(0.1, abs=0.03)    # the report rate
        assert len(observer.infos['baseBumpers'].sensor_positions) == 14
        assert not any(m.bumped for _, m in observer.events['baseBumpers'])
        # A bumper pressed in the emulator shows on the Bumper stream, then its release.
        emulator.set_bumper(0x42, 0b0101)
        observer.until(lambda o: o.events['baseBumpers'][-1][1].bumped, 'the bumper pressed', 10)
        assert [i for i, b in enumerate(observer.events['baseBumpers'][-1][1].bumpers) if b] == [2]
        emulator.set_bumper(0x42, 0)
        observer.until(lambda o: not o.events['baseBumpers'][-1][1].bumped, 'released', 10)
        # brake-reset is false: a release request is refused and never reaches the base.
        observer.request('baseDrive', brake=False, trans=0.3)
        # The refusal is logged, then the drive info says the brake is still set.
        observer.until(lambda o: 'may not release its brake' in child.stderr and o.infos['baseDrive'].brake,
                       'the refusal, and the brake set in the info', 10)
        assert emulator.brake
        assert not any(p.opcode == Mot.BRAKE_RELEASE and p.port == Port.MOT
                       for p in emulator.commands())
        assert logged(child, '[WARN] base:', 'released by hand') == 1
    assert emulator.error is None


@pytest.mark.parametrize(('robot', 'drive', 'fields'), [
    (B21R, 'SynchroDrive', ('trans', 'angular')),
    (ATRV_JR, 'RobotDrive', ('trans_velocity', 'rot_velocity')),
    (ATRV2, 'RobotDrive', ('trans_velocity', 'rot_velocity')),           # Pluto's own robot
    (B21IR, 'SynchroDrive', ('trans', 'angular')),                       # guide 10.1.5's type
])
def test_a_drive_request_moves_the_base_and_a_command_that_stops_coming_stops_it(
        ros_domain: int, tmp_path: pathlib.Path, robot: RobotParams, drive: str,
        fields: tuple[str, str]) -> None:
    speed, timeout = 0.3, 1.0
    device = (f'<device port="PORT" name="base" type="{robot.name}" brake-reset="true" '
              f'command-timeout="{timeout}"/>')
    watcher = Observer(streams('base', drive))
    try:
        with emulated(robot) as emulator:
            config = rflex_config(tmp_path, '', device=device.replace('PORT', emulator.path))
            with rflex_server(config) as child:
                watcher.until(lambda o: o.events['baseMotion'] and 'baseDrive' in o.infos
                              and not emulator.brake, 'odometry, the brake released')
                # Command at 5 Hz until the odometry has shown the base cruising for 8 samples
                # (a count of the driver's samples, not a span of the test's clock: on a loaded
                # machine a fixed 0.8 s window once held none).
                deadline = time.monotonic() + 60.0

                def cruising() -> int:
                    return sum(m.tv == pytest.approx(speed, abs=2e-3) for _, m in watcher.events['baseMotion'])

                while cruising() < 8:
                    assert time.monotonic() < deadline, 'the base never cruised for 8 odometry samples'
                    watcher.request('baseDrive', **{fields[0]: speed, fields[1]: 0.0})
                    last_request, last_wall = time.monotonic(), time.time()
                    watcher.until(lambda o: True, 'pump')
                    watcher.manager.wait(0.2)
                assert emulator.velocities()[0] == pytest.approx(speed, abs=1e-3)
                # No more commands: the watchdog stops the base.
                watcher.until(lambda o: emulator.velocities() == (0.0, 0.0), 'stopped', 10)
                assert time.monotonic() - last_request > timeout
                assert set_dirs(emulator, 0)[-1] == 0 and max(set_dirs(emulator, 0)) > 0
                watcher.until(lambda o: o.events['baseMotion'][-1][1].tv == 0.0, 'odometry at rest')
                assert logged(child, '[WARN] base:', f'no command for {timeout:.2f} s') == 1
        # Egomotion follows: x = v t while cruising (from the first sample at speed to the last
        # command), and it ends where the emulated base is.
        motion = watcher.events['baseMotion']
        first = next(s for s, m in motion if m.tv == pytest.approx(speed, abs=2e-3))
        cruise = [(s, m) for s, m in motion if first <= s <= last_wall]
        assert len(cruise) >= 5
        (s0, m0), (s1, m1) = cruise[0], cruise[-1]
        assert m1.location.x - m0.location.x == pytest.approx(speed * (s1 - s0), rel=0.1)
        assert all(m.tv == pytest.approx(speed, abs=2e-3) for _, m in cruise)
        end = watcher.events['baseMotion'][-1][1].location
        assert end.x == pytest.approx(emulator.distance_m(), abs=2e-3)
        assert (end.y, end.theta) == pytest.approx((0.0, 0.0), abs=1e-6)
        assert getattr(watcher.infos['baseDrive'], fields[0]) == 0.0
    finally:
        watcher.close()
    assert emulator.error is None


def test_a_silent_base_is_logged_and_nothing_is_published_until_it_is_back(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    data = ('baseMotion', 'baseSonar', 'baseBumpers')
    with emulated() as emulator, rflex_server(rflex_config(tmp_path, emulator.path)) as child:
        observer.until(lambda o: all(len(o.events[s]) >= 5 for s in data), 'data before the silence')
        emulator.silent.set()
        observer.until(lambda o: 'is silent' in child.stderr, 'the silence logged', timeout=10)
        # Every report read before the silence was published before it was logged; the driver
        # keeps polling the silent base for a few loop turns, in which nothing may be published.
        quiet = observer.quiet_span('base', 'loop turns while silent')
        asked = len(emulator.commands())
        observer.until(lambda o: len(emulator.commands()) > asked, 'a poll of the silent base',
                       timeout=10)
        emulator.silent.clear()
        back = time.time()
        observer.until(lambda o: 'is back' in child.stderr and all(
            sum(s > back for s in o.stamps(name)) >= 5 for name in data), 'data again', timeout=10)
        assert logged(child, '[WARN] base:', 'is silent') == 1               # once each
        assert logged(child, '[NOTICE] base:', 'is back') == 1
    assert emulator.error is None
    # Data from after the silence arrived on every stream, so all before it did: none is of the
    # silence (the streams that publish only on change may have nothing after it: still none).
    for name in observer.events:
        if not name.startswith('heartbeat/'):
            assert_none_between(observer.stamps(name), quiet, back, f'{name} while silent')


@pytest.mark.parametrize(('device', 'name', 'reason'), [
    ('<device port="/dev/null" name="base" type="B14r"/>', 'base', ':3: '),
    ('<device port="/dev/null" name="base" type="B21r"/>', 'other', ': no <device> named "other"'),
])
def test_a_bad_config_is_refused_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                     device: str, name: str, reason: str) -> None:
    path = rflex_config(tmp_path, '', device=device)
    with rflex_server(path, name) as child:
        assert child.process.wait(timeout=30) == 2
    assert f'rflex_server: {path}{reason}' in child.stderr


def test_the_shipped_config_runs_driver_and_emulator_under_the_mcp(
        observer: Observer, tmp_path: pathlib.Path) -> None:
    link = str(tmp_path / 'ttyRFLEX')
    for name in ('rflex-config.xml', 'mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_text((CONFIG / name).read_text().replace('/tmp/wurde-rflex', link))
    assert link in (tmp_path / 'mcp-config.xml').read_text()
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: all(len(o.events[s]) >= 5 for s in ('baseMotion', 'baseSonar')),
                       'base data', timeout=30)
        ranges = observer.events['baseSonar'][-1][1].ranges
        assert len(ranges) == 48 and all(r == pytest.approx(2.0, abs=1e-3) for r in ranges)
        mcp.stop(timeout=30)
    for module in ('RFLEXEmulator', 'base'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), log[-2000:]
