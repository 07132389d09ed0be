"""Simulated time at time scale 3: the dummy base publishes every step's time on /clock, an MCP
started with use_sim_time starts its modules with it, and their auto-timestamps (heartbeats), the
wrist's stamps and a client's clock are the simulator's step times — not the wall clock, which at
scale 3 falls two seconds behind every second."""

from __future__ import annotations

import bisect
import os
import pathlib

from rosgraph_msgs.msg import Clock
from sim_fixture import HEARTBEAT, Observer, heartbeat, sim_config
from wurde_core import Time
from wurde_core.ros_adaptor import take_stamped
from wurde_testing import ChildProcess, find_executable

CONFIG = '''<?xml version="1.0"?>
<mcp-config>
  <module name="PlutoBase" managed="critical">
    <binary>wurde_drivers/dummy_base</binary><options>-n PlutoBase</options>
  </module>
  <module name="PlutoWrist" managed="managed">
    <binary>wurde_drivers/dummy_wrist</binary><options>-n PlutoWrist</options>
  </module>
</mcp-config>
'''
STEP_S = 0.02          # config/sim's simulation step
WRIST_STEP_S = 0.01    # the dummy wrist's motion step


def _nearest(stamps: list[float], t: float) -> float:
    """Distance from ``t`` to the nearest of the sorted ``stamps``."""
    i = bisect.bisect_left(stamps, t)
    return min(abs(stamps[j] - t) for j in (i - 1, i) if 0 <= j < len(stamps))


def test_stamps_follow_the_simulators_clock_at_time_scale_3(ros_domain: int, tmp_path: pathlib.Path) -> None:
    sim_config(tmp_path, top={'time-scale': '3'})
    (tmp_path / 'mcp-config.xml').write_text(CONFIG)
    observer = Observer({'PlutoBaseTruth': 'Egomotion', 'PlutoWrist': 'ActuatorState',
                         **heartbeat('PlutoWrist')}, sim_time=True)
    clock = observer.manager.node.create_subscription(Clock, '/clock', lambda _: None, 10)
    clocks: list[float] = []

    def enough(o: Observer) -> bool:
        """Enough of each, counted from the first truth heard (each subscription matches in its
        own time: a loaded run heard five heartbeats before its first truth)."""
        clocks.extend(Time.from_msg(m.clock).get_seconds() for m, _ in take_stamped(clock))
        if not o.events['PlutoBaseTruth']:
            return False
        first = min(t for t, _ in o.events['PlutoBaseTruth'])
        beats = [t for t, _ in o.events[HEARTBEAT + 'PlutoWrist'] if t >= first]
        wrist = [t for t, _ in o.events['PlutoWrist'] if t >= first]
        return len([c for c in clocks if c >= first]) >= 20 and len(beats) >= 5 and len(wrist) >= 20
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a',
                           '--ros-args', '-p', 'use_sim_time:=true'], env=env):
            observer.until(enough, 'clock, wrist beats and wrist data', timeout=90)
            truth = sorted(t for t, _ in observer.events['PlutoBaseTruth'])
            observer.until(lambda o: len(o.events['PlutoBaseTruth']) > len(truth), 'truth past the wait')
            truth = sorted(t for t, _ in observer.events['PlutoBaseTruth'])
            # /clock carries the base's step times: each one is a truth stamp
            assert all(_nearest(truth, c) < 1e-6 for c in clocks if c >= truth[0])
            # the wrist's heartbeats, auto-stamped by its CommsManager (use_sim_time from the
            # MCP), carry the last /clock it had: a step time of the simulator
            beats = [t for t, _ in observer.events[HEARTBEAT + 'PlutoWrist'] if t >= truth[0]]
            assert beats and all(_nearest(truth, t) < 1e-6 for t in beats), beats[:5]
            # the wrist's motion runs on that clock: its stamps lie on the simulator's time line
            wrist = [t for t, _ in observer.events['PlutoWrist'] if truth[0] <= t <= truth[-1]]
            assert wrist and all(_nearest(truth, t) <= WRIST_STEP_S + 1e-6 for t in wrist)
            # and so does this client's own clock
            now = observer.manager.now().get_seconds()
            observer.until(lambda o: o.events['PlutoBaseTruth'][-1][0] >= now, 'the truth up to that time')
            assert _nearest(sorted(t for t, _ in observer.events['PlutoBaseTruth']), now) < 1e-6
    finally:
        observer.close()
