"""The simulated robot outlives its base driver: a dummy_base the MCP restarts puts the robot
back where it stood (wurde_core.resume), as a real robot stays where its driver died; a first
start begins at the config's start, whatever an earlier run left.

The processes get the environment the MCP gives its modules (the state file, the restart count):
the MCP's side of it is in wurde_mcp's test_supervision."""

from __future__ import annotations

import json
import math
import os
import pathlib
import signal
import time

import pytest
from sim_fixture import Observer, sim_config
from wurde_core.heartbeat import RESTART_ENV
from wurde_core.resume import STATE_ENV
from wurde_testing import ChildProcess, find_executable

WAIT_S = 60.0
START = (3.0, 7.5, 0.0)          # config/sim's start place in the office


def base(path: pathlib.Path, state: pathlib.Path, restart: int) -> ChildProcess:
    env = dict(os.environ, **{STATE_ENV: str(state), RESTART_ENV: str(restart)})
    return ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path), '-n', 'PlutoBase'],
                        env=env)


def said(child: ChildProcess, text: str) -> None:
    """Wait for ``text`` in the base's log (stderr), with a deadline."""
    deadline = time.monotonic() + WAIT_S
    while text not in child.stderr:
        assert time.monotonic() < deadline, f'the base never said {text!r}:\n{child.stderr}'
        time.sleep(0.05)


def truth(message) -> tuple[float, float, float]:
    return message.location.x, message.location.y, message.location.theta


def first_truth(observer: Observer, after: int) -> tuple[float, float, float]:
    """Where a new base process (the only one up, the last ended) has the robot: its first truth
    this observer got (those published before the subscription matched are not seen; the robot
    stands still until commanded, so any of them tells)."""
    observer.until(lambda o: len(o.events['PlutoBaseTruth']) > after, 'the new base process', WAIT_S)
    return truth(observer.events['PlutoBaseTruth'][after][1])


def test_a_restarted_base_puts_the_robot_back_where_it_stood(ros_domain: int, tmp_path: pathlib.Path) -> None:
    path = sim_config(tmp_path)
    state = tmp_path / 'PlutoBase.resume'
    observer = Observer({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseDrive/SynchroDrive': 'SynchroDrive'})
    try:
        with base(path, state, 0) as first:
            assert first_truth(observer, 0) == pytest.approx(START)
            observer.until(lambda o: o.obj('PlutoBaseDrive/SynchroDrive').peers() > 0, 'the drive', WAIT_S)

            def driven(o: Observer) -> bool:
                """Half a metre from the start; the command is sent again as a driver would (the
                base stops when commands stop coming)."""
                o.request('PlutoBaseDrive/SynchroDrive', trans=0.3, angular=0.2)
                return math.dist(truth(o.events['PlutoBaseTruth'][-1][1])[:2], START[:2]) > 0.5
            observer.until(driven, 'the robot half a metre from its start', WAIT_S)
            observer.request('PlutoBaseDrive/SynchroDrive', trans=0.0, angular=0.0)
            observer.until(lambda o: o.events['PlutoBaseTruth'][-1][1].tv == 0.0
                           and o.events['PlutoBaseTruth'][-1][1].rv == 0.0, 'the robot at rest', WAIT_S)

            def saved_at_rest(o: Observer) -> bool:
                try:
                    kept = json.loads(state.read_text())
                except (OSError, ValueError):
                    return False
                return (kept['x'], kept['y'], kept['theta']) == truth(o.events['PlutoBaseTruth'][-1][1])
            observer.until(saved_at_rest, 'the pose at rest saved', WAIT_S)
            stood = truth(observer.events['PlutoBaseTruth'][-1][1])
            first.process.send_signal(signal.SIGKILL)
            first.process.wait(timeout=WAIT_S)
        seen = len(observer.events['PlutoBaseTruth'])
        with base(path, state, 1) as restarted:
            assert first_truth(observer, seen) == pytest.approx(stood, abs=1e-9)
            said(restarted, 'resumed: restart 1')
        # A new run (the MCP's first start of the base) begins at the start, not where the last
        # run ended.
        seen = len(observer.events['PlutoBaseTruth'])
        with base(path, state, 0) as fresh:
            assert first_truth(observer, seen) == pytest.approx(START)
            said(fresh, 'the start of the config: a first start')
    finally:
        observer.close()


def test_a_restart_with_a_bad_state_file_starts_at_the_start_and_says_why(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    path = sim_config(tmp_path)
    state = tmp_path / 'PlutoBase.resume'
    state.write_text('{"x": 1.0}')
    observer = Observer({'PlutoBaseTruth': 'Egomotion'})
    try:
        with base(path, state, 2) as restarted:
            assert first_truth(observer, 0) == pytest.approx(START)
            said(restarted, 'no pose in the saved state')
    finally:
        observer.close()


def test_a_base_killed_while_turning_resumes_at_its_last_odometry(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """Killed while it drives and turns (1 rad/s), the base comes back where its last odometry
    sample put the robot: the consumers bridge the restart on that sample
    (pluto_nav.continuous_odometry), so the robot must not have moved from it.  A pose saved on
    a clock of its own came back up to 0.066 rad off that sample, and the guide's avoider ended
    0.33 m from its goal.  config/sim's odometry is exact (no noise): the odometry is the truth
    in the frame of the start place."""
    path = sim_config(tmp_path)
    state = tmp_path / 'PlutoBase.resume'
    observer = Observer({'PlutoBaseTruth': 'Egomotion', 'PlutoBaseMotion': 'Egomotion',
                         'PlutoBaseDrive/SynchroDrive': 'SynchroDrive'})
    try:
        with base(path, state, 0) as first:
            first_truth(observer, 0)
            observer.until(lambda o: o.obj('PlutoBaseDrive/SynchroDrive').peers() > 0, 'the drive', WAIT_S)

            def turning(o: Observer) -> bool:
                o.request('PlutoBaseDrive/SynchroDrive', trans=0.3, angular=1.0)
                return bool(o.events['PlutoBaseMotion']) and o.events['PlutoBaseMotion'][-1][1].rv > 0.9
            observer.until(turning, 'the robot turning at 1 rad/s', WAIT_S)

            def between_samples(o: Observer) -> bool:
                """Killed just after an odometry sample, the pose saved with it is the last
                one: the kill comes between two (10 Hz), past the middle."""
                since = o.stamps('PlutoBaseTruth')[-1] - o.stamps('PlutoBaseMotion')[-1]
                return 0.055 < since < 0.095
            observer.until(between_samples, 'the simulation between two odometry samples', WAIT_S)
            first.process.send_signal(signal.SIGKILL)
            first.process.wait(timeout=WAIT_S)
            killed = time.time()
        seen = len(observer.events['PlutoBaseTruth'])
        with base(path, state, 1) as restarted:
            resumed = first_truth(observer, seen)        # what the dead process sent has come by now
            said(restarted, 'resumed: restart 1')
            # The restarted base's odometry counts from zero again; its samples come in among the
            # dead process's (on a loaded machine before the first truth above), so the last
            # sample is the dead process's last by its stamp: the simulated clock starts at its
            # process's start and never runs ahead of the wall, so the dead process stamped
            # everything before the kill and the new one everything after it.
            observer.until(lambda o: o.stamps('PlutoBaseMotion')[-1] > killed, "the restarted base's odometry",
                           WAIT_S)
        last = truth([message for stamp, message in observer.events['PlutoBaseMotion'] if stamp < killed][-1])
        sx, sy, st = START
        expected = (sx + last[0] * math.cos(st) - last[1] * math.sin(st),
                    sy + last[0] * math.sin(st) + last[1] * math.cos(st), st + last[2])
        assert resumed[:2] == pytest.approx(expected[:2], abs=1e-6)
        assert math.remainder(resumed[2] - expected[2], math.tau) == pytest.approx(0.0, abs=1e-6)
    finally:
        observer.close()
