"""The simulated Pluto on one host and a client with its own MCP on another (issue 16).

Run by ``make two-hosts`` (it needs root for network namespaces, so ``make test`` skips it; the
loopback version, ``test_two_mcps.py``, runs in ``make test``).  Host ``robot`` runs
config/pluto (the dummies, localization, the drive → avoid → motion chain) under the seed's MCP;
host ``desktop`` runs MCP_B with Watcher, whose STRAT_ASSIGNED Pose consumer is mapped to the
robot's ``Localization/Pose``.  Each MCP lists the other host's modules as external.  Shown:
heartbeats and module tables cross; the assignment connects the consumer on one host to the
supplier on the other; a client script on the desktop (``mission``) drives the robot to a place;
``turn_off`` on the desktop reaches the robot's module through its own
MCP; the link cut for 10 s makes each side mark the other's modules lost within their TTL while
nothing on the robot stops, and everything comes back when the link does, the losses counted.
"""

from __future__ import annotations

import os
import pathlib
import re
import time

import pytest

from mcp_fixture import wait_output
from netns_fixture import Host, TwoHosts, can_make_namespaces
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO = ROOT / 'config' / 'pluto'
CUT_S = 10.0
ROBOT_MODULES = ('PlutoBase', 'PlutoLaser', 'PlutoWrist', 'PlutoDMU', 'PlutoGPS', 'localModule',
                 'poseModule', 'driveModule', 'avoidModule', 'motionModule', 'map_server',
                 'navigator')
#: The robot's modules the desktop's MCP watches.
WATCHED = ('PlutoBase', 'localModule')
#: A silent module is marked lost this long after its TTL at most (the MCP's grace and loop).
LOST_SLACK_S = 0.5

pytestmark = pytest.mark.skipif(os.environ.get('WURDE_TWO_HOSTS') != '1',
                                reason='needs root and network namespaces: make two-hosts')

WATCHER = (
    '#!/usr/bin/env python3\n'
    'import sys\n'
    'from wurde_core import CommsManager, ConnectionStrategy, RunState\n'
    'from wurde_core.interfaces import LocalizationPose\n'
    'm = CommsManager("Watcher"); m.parse_options(sys.argv); m.set_sleep(0.1)\n'
    'pose = LocalizationPose(ConnectionStrategy.ASSIGNED, "PoseClient")\n'
    'm.register_consumer(pose)\n'
    'n = 0\n'
    'while m.run_update() != RunState.QUIT:\n'
    '    while pose.get_next_data():\n'
    '        n += 1\n'
    '        print("POSE", n, flush=True)\n'
    'm.clean_up()\n')

NOTICED = (r'MCP: (?P<name>\w+) missed its TTL \((?P<ttl>[0-9.]+) s\): zombie \(noticed at '
           r'monotonic (?P<at>[0-9.]+)')


def table(host: Host, env: dict[str, str], mcp: str | None = None) -> dict[str, dict[str, str]]:
    """An MCP's module table, read by mcp_controller on ``host`` (``mcp``: that MCP's name)."""
    argv = [find_executable('wurde_mcp', 'mcp_controller'), *(['--mcp', mcp] if mcp else []),
            'list']
    result = host.run(argv, env)
    assert result.returncode == 0, result.stderr
    rows = {}
    for line in result.stdout.splitlines()[1:]:
        parts = line.split()
        if len(parts) == 7:  # no host yet: a module not heard
            parts.insert(5, '')
        name, status, _managed, state, pid, where, _age, restarts = parts
        rows[name] = dict(status=status, state=state, pid=pid, host=where, restarts=restarts)
    return rows


def until(read, predicate, what: str, timeout: float = 180.0):
    """The first value of ``read()`` for which ``predicate`` holds (failure bound ``timeout``)."""
    deadline = time.monotonic() + timeout
    while True:
        value = read()
        if predicate(value):
            return value
        assert time.monotonic() < deadline, f'{what} not within {timeout} s: {value}'


def poses(log: pathlib.Path) -> int:
    text = log.read_text() if log.exists() else ''
    return sum(line.startswith('POSE ') for line in text.splitlines())


def lost(mcp: ChildProcess) -> dict[str, tuple[float, float]]:
    """``{module: (ttl, noticed at)}`` of every module the MCP marked lost (a zombie)."""
    return {m['name']: (float(m['ttl']), float(m['at']))
            for m in re.finditer(NOTICED, mcp.stderr)}


def test_robot_and_desktop_over_a_link_that_is_cut(tmp_path, ros_domain) -> None:
    why = can_make_namespaces()
    assert why is None, f'make two-hosts cannot build two hosts here: {why}'
    robot_dir, desktop_dir = tmp_path / 'robot', tmp_path / 'desktop'
    robot_dir.mkdir()
    desktop_dir.mkdir()
    # The robot: config/pluto, and the desktop's Watcher listed as external.
    config = (PLUTO / 'mcp-config.xml').read_text().replace(
        '</mcp-config>', '  <module name="Watcher" locale="external"/>\n</mcp-config>')
    (robot_dir / 'mcp-config.xml').write_text(config)
    # The desktop: Watcher, and the robot's base (critical) and localModule as external.
    watcher = desktop_dir / 'watcher.py'
    watcher.write_text(WATCHER)
    watcher.chmod(0o755)
    (desktop_dir / 'mcp-config.xml').write_text(
        f'<mcp-config>\n  <module name="Watcher" binary="{watcher}"/>\n'
        '  <module name="PlutoBase" locale="external" managed="critical"/>\n'
        '  <module name="localModule" locale="external"/>\n</mcp-config>\n')
    (desktop_dir / 'mcp-mappings.xml').write_text(
        '<mcp-mappings>\n  <connect module="Watcher">\n    <input interface="LocalizationPose" '
        'source="Localization/Pose" object="PoseClient"/>\n  </connect>\n</mcp-mappings>\n')
    hosts = TwoHosts(ros_domain)
    robot, desktop = hosts.a, hosts.b
    env_robot = hosts.env(robot, ros_domain, WURDE_CONFIG_DIR=str(PLUTO),
                          WURDE_LOG_DIRECTORY=str(robot_dir))
    env_desktop = hosts.env(desktop, ros_domain, WURDE_MCP_NAME='MCP_B',
                            WURDE_LOG_DIRECTORY=str(desktop_dir))
    mcp = find_executable('wurde_mcp', 'mcp')
    watcher_log = desktop_dir / 'mcp-modules' / 'Watcher.log'
    try:
        with robot.start([mcp, '-c', str(robot_dir / 'mcp-config.xml'),
                          '-m', str(PLUTO / 'mcp-mappings.xml'), '-a'], env_robot) as mcp_a, \
                desktop.start([mcp, '-c', str(desktop_dir / 'mcp-config.xml'),
                               '-m', str(desktop_dir / 'mcp-mappings.xml'), '-a'],
                              env_desktop) as mcp_b:
            mcp_a.expect('MCP ready', timeout=120)
            mcp_b.expect('MCP ready', timeout=120)
            # Heartbeats and tables cross: the desktop's MCP sees the robot's modules alive, on
            # host robot; the robot's table, read from the desktop, has all its modules and
            # the desktop's Watcher.
            rows_b = until(lambda: table(desktop, env_desktop),
                           lambda r: all(r[m]['status'] == 'ACTIVE' for m in ('Watcher', *WATCHED)),
                           'the desktop MCP\'s modules alive')
            assert {rows_b[m]['host'] for m in WATCHED} == {'robot'}, rows_b
            assert rows_b['Watcher']['host'] == 'desktop', rows_b
            rows_a = until(lambda: table(desktop, env_desktop, mcp='MCP'),
                           lambda r: all(r.get(m, {}).get('status') == 'ACTIVE'
                                         for m in (*ROBOT_MODULES, 'Watcher')),
                           'the robot\'s table, read on the desktop')
            assert rows_a['Watcher']['host'] == 'desktop' and rows_a['PlutoBase']['host'] == 'robot'
            # STRAT_ASSIGNED across the link: the desktop's MCP gave Watcher the robot's Pose.
            until(lambda: poses(watcher_log), lambda n: n >= 5, 'Pose on the desktop')
            before = {m: (rows_a[m]['pid'], rows_a[m]['restarts']) for m in ROBOT_MODULES}

            # The link is cut for 10 s.
            exits = mcp_a.stderr.count('exited with code')  # the registration runs' so far
            cut_at = time.monotonic()
            hosts.cut()
            until(lambda: set(lost(mcp_b)), lambda s: s >= set(WATCHED),
                  'the desktop marking the robot\'s modules lost', 30)
            until(lambda: set(lost(mcp_a)), lambda s: 'Watcher' in s,
                  'the robot marking Watcher lost', 30)
            delays = {name: at - cut_at for mcp_x in (mcp_a, mcp_b)
                      for name, (_ttl, at) in lost(mcp_x).items()}
            ttls = {**{n: t for n, (t, _) in lost(mcp_a).items()},
                    **{n: t for n, (t, _) in lost(mcp_b).items()}}
            print('lost after the cut (s):', {n: round(d, 3) for n, d in delays.items()},
                  'TTLs:', ttls)
            for name, delay in delays.items():
                assert delay <= ttls[name] + LOST_SLACK_S, (name, delay, ttls[name])
            wait_output(mcp_b, r'MCP: critical module PlutoBase is down')
            count_at_cut = poses(watcher_log)
            time.sleep(max(0.0, cut_at + CUT_S - time.monotonic()))  # the cut's length is the test
            hosts.connect()
            up_at = time.monotonic()

            # Everything comes back: the tables, the Pose on the desktop.
            rows_b = until(lambda: table(desktop, env_desktop),
                           lambda r: all(r[m]['status'] == 'ACTIVE' for m in ('Watcher', *WATCHED))
                           and r['Watcher']['state'] == 'RUN', 'the desktop back in Run', 120)
            rows_a = until(lambda: table(robot, env_robot),
                           lambda r: r['Watcher']['status'] == 'ACTIVE', 'Watcher back', 120)
            until(lambda: poses(watcher_log), lambda n: n >= count_at_cut + 5,
                  'Pose on the desktop after the link is back', 120)
            print(f'back {time.monotonic() - up_at:.1f} s after the link came up')
            # Nothing on the robot stopped: same processes, no restarts.
            after = {m: (rows_a[m]['pid'], rows_a[m]['restarts']) for m in ROBOT_MODULES}
            assert after == before
            assert all(rows_a[m]['status'] == 'ACTIVE' for m in ROBOT_MODULES), rows_a
            assert mcp_a.stderr.count('exited with code') == exits, mcp_a.stderr
            # The losses are counted: each side lost exactly the other's modules, once each.
            assert sorted(lost(mcp_b)) == sorted(WATCHED)
            assert sorted(lost(mcp_a)) == ['Watcher']
            # The desktop's MCP commanded none of the robot's modules.
            wait_output(mcp_b, r'MCP: PlutoBase belongs to MCP "MCP": it is watched, not '
                               r'commanded, from here')

            # A client script on the desktop (the mission client of make demo, not under MCP_B)
            # sends the robot to a place by name across the link: the navigator, the chain and the
            # Pose all live on the robot.
            mission = desktop.run(
                [find_executable('pluto_motion', 'mission'), '-m', str(PLUTO / 'map.xml'),
                 '-P', 'office2', '-O', str(desktop_dir / 'mission')],
                {k: v for k, v in env_desktop.items() if k != 'WURDE_MCP_NAME'}, timeout=400)
            assert mission.returncode == 0 and 'mission: office2 (7.5, 3): reached' in \
                mission.stdout, mission.stdout + mission.stderr
            print([line for line in mission.stdout.splitlines() if 'reached' in line])

            # turn_off on the desktop reaches the robot's poseModule through the robot's MCP,
            # which keeps it down.
            off = desktop.run([find_executable('wurde_mcp', 'turn_off'), 'poseModule'],
                              env_desktop)
            assert off.returncode == 0, off.stderr
            assert 'asked the MCP on mcp_control to quit poseModule' in off.stdout, off.stdout
            until(lambda: table(desktop, env_desktop, mcp='MCP'),
                  lambda r: r['poseModule']['status'] == 'DEAD', 'poseModule stopped')
            for process in (mcp_b, mcp_a):
                assert process.stop(timeout=60) == 0, process.stderr
            wait_output(mcp_b, r'supervision summary: 2 zombies')
            wait_output(mcp_a, r'supervision summary: 1 zombies')
    finally:
        hosts.close()
