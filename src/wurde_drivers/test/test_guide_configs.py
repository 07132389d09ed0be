"""The guide's MCP configurations as printed, every module up against the device emulators.

Chapter 1's ``config/guide-ch1`` (1.1.5: ``sickServer``, ``safePTUserver``, ``rFlexServerII``,
``vectorMover``, ``laserAvoider``) and the appendix's ``config/guide-appendix/robot.xml`` (10.1.1:
``rFlexServer``, ``sickLaser``, ``synchroMover``, ``laserAvoider``, ``fooServer``,
``visionModule``) are started with the guide's command line (chapter 6: ``mcp -c ... -m ...``,
no ``-a``), their drivers on emulators over pseudo-terminals.  Each module must be ACTIVE and in
Run in the MCP's table, the external ones (named without a binary) listed, and data must flow:
the drivers' streams, the avoider's status, FooServer's Bar, and the vision module's data sets
(laser and odometry the MCP assigned it).
"""

from __future__ import annotations

import os
import pathlib
import shutil

import pytest
from sim_fixture import Observer
from wurde_core import RunState, StatusMode
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
CH1, APPENDIX = ROOT / 'config' / 'guide-ch1', ROOT / 'config' / 'guide-appendix'

#: case: config directory, its device files, (emulator, its options, the shipped port), the MCP's
#: files, the modules that run, the external ones, streams that must carry data.
CASES = {
    'chapter1': (
        CH1, ('laser-config.xml', 'rflex-config.xml', 'ptu-config.xml'),
        [('sick_emulator', ['-n', 'LMSEmulator', '-k', 'LMS', '-w', '1.2,4.5,2.5'], '/tmp/wurde-guide-sick'),
         ('rflex_emulator', ['-n', 'RFlexEmulator', '-t', 'ATRVJr'], '/tmp/wurde-guide-rflex'),
         ('ptu_emulator', ['-n', 'PTUEmulator'], '/tmp/wurde-guide-ptu')],
        ['-c', str(CH1 / 'mcp-config.xml'), '-m', str(CH1 / 'mcp-mappings.xml')],
        ('VectorMover', 'laserAvoider', 'HollowayLMS', 'safePTUserver', 'HollowayRFlex'),
        ('BlindTeleop',),
        {'HollowayLMS': 'RangeFinder', 'HollowayRFlexMotion': 'Egomotion', 'SafePTUServer': 'PTUnit',
         'SimpleAvoider': 'ObstacleAvoiderTransport'}),
    'appendix': (
        APPENDIX, ('laser-config.xml', 'rflex-config.xml', 'camera-config.xml',
                   'local-vision-config.xml'),
        [('sick_emulator', ['-n', 'PLSEmulator', '-k', 'PLS', '-w', '1.2,4.5,2.5'], '/tmp/wurde-guide-pls'),
         ('rflex_emulator', ['-n', 'RFlexEmulator', '-t', 'B21ir'], '/tmp/wurde-guide-b21')],
        ['-c', str(APPENDIX / 'robot.xml')],
        ('TomRFlex', 'TomPLS', 'SynchroMover', 'laserAvoider', 'FooServer', 'StereoVisionModule'),
        ('BlindTeleop', 'FooClient', 'Eye'),
        {'TomPLS': 'RangeFinder', 'TomRFlexMotion': 'Egomotion', 'Bar': 'Foo',
         'SimpleAvoider': 'ObstacleAvoiderTransport'}),
}


def _table(observer: Observer) -> dict[str, tuple[StatusMode, RunState]]:
    """The MCP's newest module table: name -> (status, run state)."""
    events = observer.events['mcp_control']
    if not events:
        return {}
    data = events[-1][1]
    return {name: (StatusMode(status.value), RunState(state.value))
            for name, status, state in zip(data.module_names, data.module_status, data.module_state)}


@pytest.mark.parametrize('case', CASES)
def test_the_guides_configuration_runs_as_printed(case: str, ros_domain: int,
                                                  tmp_path: pathlib.Path) -> None:
    directory, device_files, emulators, mcp_args, running, external, streams = CASES[case]
    for name in device_files:       # the ports made the test's own
        text = (directory / name).read_text()
        for _, _, port in emulators:
            text = text.replace(port, str(tmp_path / pathlib.Path(port).name))
        (tmp_path / name).write_text(text)
    if (directory / 'playback').is_dir():
        shutil.copytree(directory / 'playback', tmp_path / 'playback')
    data_dir = tmp_path / 'data'
    data_dir.mkdir()
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path),
               WURDE_DATA_DIR=str(data_dir))
    observer = Observer({'mcp_control': 'SimpleControl', **streams})
    children: list[ChildProcess] = []
    try:
        for program, options, port in emulators:
            children.append(ChildProcess([find_executable('wurde_drivers', program), *options,
                                          '-p', str(tmp_path / pathlib.Path(port).name)], env=env))
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), *mcp_args], env=env,
                          cwd=str(tmp_path)) as mcp:
            mcp.expect('MCP ready', timeout=120)

            def up(o: Observer) -> bool:
                table = _table(o)
                return (all(table.get(m) == (StatusMode.ACTIVE, RunState.RUN) for m in running)
                        and all(m in table for m in external))

            try:
                observer.until(up, 'every module ACTIVE in Run', timeout=180)
                observer.until(lambda o: all(len(o.events[s]) >= 3 for s in streams),
                               'data on every stream', timeout=120)
            except AssertionError as error:
                raise AssertionError(f'{error}\ntable: {_table(observer)}\n'
                                     f'MCP:\n{mcp.stderr[-6000:]}') from None
            table = _table(observer)
            assert set(table) == set(running) | set(external), table
            assert all(table[m][0] != StatusMode.ACTIVE for m in external), table
            if case == 'appendix':      # the StereoDataCollector got TomPLS and TomRFlexMotion
                observer.until(lambda o: all(any(data_dir.glob(f'Data-*-{kind}-*.txt'))
                                             for kind in ('laser', 'odometry')),
                               'the vision module\'s laser and odometry sets', timeout=60)
            assert mcp.stop(timeout=60) == 0
    finally:
        for child in children:
            child.stop()
        observer.close()
    for module in running:
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert 'Traceback' not in log, log[-3000:]
