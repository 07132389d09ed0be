"""The dummy DMU across a gap in the base's truth: a robot that stopped is not turned by the DMU.

Issue 38: a SIGSTOPped base leaves seconds without truth while the robot stands; the dummy
integrated the last rate over the whole gap, and the localModule turned a resting robot by 98°.
"""

from __future__ import annotations

import math
import pathlib

from sim_fixture import Observer, sim_config
from wurde_core import Pose, Time
from wurde_core.interfaces import Egomotion
from wurde_testing import ChildProcess, find_executable

RATE = 0.5          # rad/s, turning in place before and after the gap
STEP = 0.02         # the base's simulation step (s)


def _truth_samples(start: float, seconds: float, theta0: float) -> list[tuple[float, float]]:
    """(stamp, theta) every simulation step of a turn in place at :data:`RATE`."""
    n = round(seconds / STEP)
    return [(start + i * STEP, theta0 + RATE * i * STEP) for i in range(n + 1)]


def test_a_gap_in_the_truth_is_no_turn(ros_domain: int, tmp_path: pathlib.Path) -> None:
    path = sim_config(tmp_path)
    observer = Observer({'PlutoDMU': 'DMUState'})
    truth = Egomotion('PlutoBaseTruth')
    truth.set_queue_mode(True)
    truth.set_auto_timestamp(False)
    observer.manager.register_supplier(truth)
    before = _truth_samples(100.0, 1.0, 0.0)
    after = _truth_samples(104.0, 1.0, before[-1][1])    # 3 s without truth: the robot stood

    def send(samples: list[tuple[float, float]]) -> None:
        for stamp, theta in samples:
            truth.data.location = Pose(3.0, 7.5, theta)
            truth.data.tv, truth.data.rv, truth.data.acceleration = 0.0, RATE, 0.0
            truth.data.timestamp = Time(stamp)
            truth.publish_data()

    program = find_executable('wurde_drivers', 'dummy_dmu')
    with ChildProcess([program, '-c', str(path), '-n', 'PlutoDMU']) as child:
        observer.until(lambda o: truth.peers('data') > 0, 'the dummy DMU reads the truth')
        send(before)
        observer.until(lambda o: o.stamps('PlutoDMU') and o.stamps('PlutoDMU')[-1] > 100.9,
                       'the DMU up to the gap')
        send(after)
        observer.until(lambda o: o.stamps('PlutoDMU')[-1] > 104.9, 'the DMU after the gap')
        assert child.stop() == 0
    events = observer.events['PlutoDMU']
    stamps = [stamp for stamp, _ in events]
    thetas = [message.theta for _, message in events]
    # The filtered state's stamps are earlier by its delay: compare turns between two stamps.
    first = next(i for i, s in enumerate(stamps) if s > 100.2)
    last = len(stamps) - 1
    turn = thetas[last] - thetas[first]
    true_turn = RATE * ((100.0 + 1.0 - stamps[first]) + (stamps[last] - 104.0))
    assert math.isclose(turn, true_turn, abs_tol=0.03), (turn, true_turn)
    # A DMU samples on: the gap holds samples at its rate, none turning.
    inside = [t for s, t in zip(stamps, thetas) if 101.5 < s < 103.5]
    assert len(inside) > 50
    assert max(inside) - min(inside) < 0.01
