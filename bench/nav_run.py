"""One localization run in the simulator under the MCP, measured against the simulator's truth.

Used by ``bench/nav_accuracy.py`` (poseModule) and ``bench/nav_slam.py`` (slamModule).  A run:

1. writes a config directory: config/pluto's sim-config (odometry noise trans 0.05, rot 0.05,
   drift 0.02; laser noise 0.01 m; DMU rate noise on) with the given map, and an MCP config with the
   dummies, ``local_module`` and (unless ``estimator=None``) ``pose_module``;
2. starts the MCP, then ``tour -L Localization/Pose``: the robot steers by the localization's own
   estimate through a route of waypoints (generated in free space by
   :func:`wurde_drivers.sim.route.random_route`), so a localization that fails runs into walls;
3. records the truth (``PlutoBaseTruth``), raw odometry (``PlutoBaseMotion``), dead reckoning (0)
   and Pose (3), and compares each estimate with the truth interpolated at its stamps.

Optionally the localModule starts from a pose off by ``start_error`` (metres, radians), to measure
recovery: the distance driven until the Pose error stays under 10 cm.
"""

from __future__ import annotations

import bisect
import dataclasses
import math
import os
import pathlib
import sys
import time
from collections.abc import Sequence

import numpy as np
from lxml import etree
from pluto_nav.pose_history import TRUTH_GAP_S

ROOT = pathlib.Path(__file__).resolve().parents[1]
PLUTO = ROOT / 'config' / 'pluto'
POSE_STREAM = 'Localization/Pose'
DR_STREAM = 'Localization/Dead-Reckoning'
POST_STREAM = 'Localization/Post_Pose'
RECOVERED_M = 0.10
MOVEMENT_CHAIN = ('driveModule', 'avoidModule', 'motionModule', 'navigator', 'map_server')
#: The benchmark's ROS domain, claimed by :func:`bench_setup` and held until the process ends.
_CLAIM = None


@dataclasses.dataclass
class Track:
    """Stamped (x, y, theta) samples."""

    stamps: list[float] = dataclasses.field(default_factory=list)
    poses: list[tuple[float, float, float]] = dataclasses.field(default_factory=list)

    def add(self, stamp: float, x: float, y: float, theta: float) -> None:
        if self.stamps and stamp <= self.stamps[-1]:
            return
        self.stamps.append(stamp)
        self.poses.append((x, y, theta))

    def at(self, t: float) -> tuple[float, float, float] | None:
        """The pose at ``t``, interpolated; None outside the track or between two samples more
        than :data:`pluto_nav.pose_history.TRUTH_GAP_S` apart (lost)."""
        i = bisect.bisect_left(self.stamps, t)
        if i == 0 or i >= len(self.stamps):
            return self.poses[0] if self.stamps and t == self.stamps[0] else None
        (ta, a), (tb, b) = (self.stamps[i - 1], self.poses[i - 1]), (self.stamps[i], self.poses[i])
        if tb - ta > TRUTH_GAP_S:
            return None
        f = (t - ta) / (tb - ta)
        turn = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
        return a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * turn

    def length(self) -> float:
        return sum(math.dist(a[:2], b[:2]) for a, b in zip(self.poses, self.poses[1:]))


@dataclasses.dataclass
class Errors:
    """An estimate's errors against the truth."""

    position_rmse: float
    heading_rmse_deg: float
    position_max: float
    samples: int
    recovered_after_m: float | None = None     # distance driven until the error stayed < 10 cm


def compare(estimate: Track, truth: Track, *, skip_until: float = -math.inf) -> Errors:
    """Errors of ``estimate`` at its stamps against the truth interpolated there."""
    position, heading = [], []
    stamps = []
    for t, pose in zip(estimate.stamps, estimate.poses):
        true = truth.at(t)
        if true is None or t < skip_until:
            continue
        position.append(math.hypot(pose[0] - true[0], pose[1] - true[1]))
        heading.append(math.atan2(math.sin(pose[2] - true[2]), math.cos(pose[2] - true[2])))
        stamps.append(t)
    if not position:
        return Errors(math.nan, math.nan, math.nan, 0)
    errors = Errors(float(np.sqrt(np.mean(np.square(position)))),
                    float(np.degrees(np.sqrt(np.mean(np.square(heading))))), float(max(position)), len(position))
    # Recovery: the distance the truth drove until the error stayed under 10 cm for good.
    above = [i for i, e in enumerate(position) if e >= RECOVERED_M]
    if not above:
        errors.recovered_after_m = 0.0
    elif above[-1] < len(position) - 1:
        last_bad = stamps[above[-1]]
        driven = Track()
        for t, p in zip(truth.stamps, truth.poses):
            if stamps[0] <= t <= last_bad:
                driven.add(t, *p)
        errors.recovered_after_m = driven.length()
    return errors


@dataclasses.dataclass
class RunResult:
    name: str
    driven_m: float
    reached: bool
    bumped: bool
    pose: Errors
    dead_reckoning: Errors
    odometry: Errors
    seconds: float
    tour_output: str


def write_config(directory: pathlib.Path, map_file: pathlib.Path, *, estimator: str | None, seed: int,
                 time_scale: float, start_error: tuple[float, float, float] | None,
                 estimator_options: str = '-m map.xml', chain: bool = False) -> None:
    """config/pluto in ``directory`` with ``map_file``; the estimator module (poseModule or
    slamModule, with ``estimator_options``) is the only one in the MCP config, and the movement
    chain is there only with ``chain``."""
    directory.mkdir(parents=True, exist_ok=True)
    (directory / 'map.xml').write_bytes(map_file.read_bytes())
    tree = etree.parse(str(PLUTO / 'sim-config.xml'))
    tree.getroot().set('seed', str(seed))
    tree.getroot().set('time-scale', str(time_scale))
    tree.write(str(directory / 'sim-config.xml'))
    config = etree.parse(str(PLUTO / 'mcp-config.xml'))
    root = config.getroot()
    if start_error is not None:
        from wurde_idl.mapfile import load_map_data
        place = load_map_data(map_file).places['start']
        (directory / 'start.txt').write_text(f'{place.x + start_error[0]} {place.y + start_error[1]} '
                                             f'{place.theta + start_error[2]}\n')
        for node in root.iter('module'):
            if node.get('name') == 'localModule':
                node.find('options').text += ' -p start.txt'
    for node in list(root.iter('module')):
        # The estimator is added below; the movement chain is left out (tour drives the base, and
        # bench/nav_motion.py keeps it by ``chain=True``).
        if node.get('name') in ('poseModule', 'slamModule') or (not chain and node.get('name') in MOVEMENT_CHAIN):
            root.remove(node)
    if estimator is not None:
        module = etree.SubElement(root, 'module', name=estimator, managed='managed')
        etree.SubElement(module, 'binary').text = f'pluto_nav/{estimator.replace("Module", "_module")}'
        etree.SubElement(module, 'options').text = f'-n {estimator} {estimator_options}'
    config.write(str(directory / 'mcp-config.xml'))
    (directory / 'mcp-mappings.xml').write_bytes((PLUTO / 'mcp-mappings.xml').read_bytes())


def run(name: str, map_file: pathlib.Path, route: Sequence[tuple[float, float]], directory: pathlib.Path, *,
        estimator: str | None = 'poseModule', seed: int = 1, time_scale: float = 1.0,
        start_error: tuple[float, float, float] | None = None, limit_s: float = 900.0,
        estimator_options: str = '-m map.xml') -> RunResult:
    """Run the robot through ``route`` on ``map_file`` and measure; needs env.sh's environment.
    The run's files (its config, tour.png, what the modules save) stay in ``directory``."""
    from wurde_core import CommsManager
    from wurde_core.interfaces import Egomotion, LocalizationPose
    from wurde_testing import ChildProcess, find_executable

    write_config(directory, map_file, estimator=estimator, seed=seed, time_scale=time_scale,
                 start_error=start_error, estimator_options=estimator_options)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(directory), WURDE_LOG_DIRECTORY=str(directory),
               WURDE_DATA_DIR=str(directory))
    manager = CommsManager(f'NavBench{os.getpid()}')
    manager.set_no_sleep()
    truth_obj, odometry_obj = Egomotion('PlutoBaseTruth'), Egomotion('PlutoBaseMotion')
    pose_obj, dr_obj = LocalizationPose(POSE_STREAM), LocalizationPose(DR_STREAM)
    for obj in (truth_obj, odometry_obj, pose_obj, dr_obj):
        obj.set_queue_mode(True)
        manager.register_consumer(obj)
    truth, odometry, pose, dr = Track(), Track(), Track(), Track()

    def take() -> None:
        manager.step()
        while truth_obj.get_next_data():
            loc = truth_obj.data.location
            truth.add(truth_obj.data.timestamp.get_seconds(), loc.x(), loc.y(), loc.theta())
        while odometry_obj.get_next_data():
            loc = odometry_obj.data.location
            odometry.add(odometry_obj.data.timestamp.get_seconds(), loc.x(), loc.y(), loc.theta())
        for obj, track in ((pose_obj, pose), (dr_obj, dr)):
            while obj.get_next_data():
                p = obj.data.pose
                track.add(obj.data.timestamp.get_seconds(), p.x(), p.y(), p.theta())

    started = time.monotonic()
    waypoints = ' '.join(f'{x:.3f},{y:.3f}' for x, y in route)
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(directory / 'mcp-config.xml'),
                           '-m', str(directory / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=120)
            with ChildProcess([find_executable('wurde_drivers', 'tour'), '-c', str(directory / 'sim-config.xml'),
                               '-w', waypoints, '-L', POSE_STREAM, '-p', str(directory / 'tour.png'),
                               '-t', str(limit_s)], env=env) as tour:
                while tour.process.poll() is None:
                    take()
                    manager.wait(0.05)
                take()
                tour_output = tour.stdout
                (directory / 'tour.txt').write_text(tour_output + tour.stderr)
    finally:
        manager.clean_up()
    start = _start_of(map_file)
    raw = Track()     # the base's odometry placed at the start place: odometry alone
    for t, (x, y, theta) in zip(odometry.stamps, odometry.poses):
        c, s = math.cos(start[2]), math.sin(start[2])
        raw.add(t, start[0] + c * x - s * y, start[1] + s * x + c * y, start[2] + theta)
    return RunResult(name, truth.length(), 'waypoints reached' in tour_output and ' all of ' in tour_output,
                     'bumper pressed' in tour_output, compare(pose, truth), compare(dr, truth),
                     compare(raw, truth), time.monotonic() - started, tour_output)


def bench_setup(command: str, shipped: str, generated: int, seed: int, kinds: str = ''
                ) -> tuple[pathlib.Path, list[tuple[str, pathlib.Path]]]:
    """What both navigation benchmarks do first: refuse to run without DDS on loopback, claim a
    domain id, make a work directory, and list the maps: the ``shipped`` ones (comma-separated
    names in config/maps) and ``generated`` generated ones (``kinds``, comma-separated, default
    every kind, in turn; seeds from ``seed``)."""
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit(f'bench: run it through `{command}` or env.sh (DDS on loopback only)')
    import tempfile

    from wurde_drivers.sim.generate import KINDS, random_map
    from wurde_drivers.sim.mapfile import save_map
    from wurde_testing import claim_domain_id
    global _CLAIM
    # Held for the whole run: a claim dropped at once (its lock freed when the object went) let a
    # test claim the same domain, and its robot's odometry mixed with the benchmark's (2026-12-04).
    _CLAIM = claim_domain_id()
    os.environ['ROS_DOMAIN_ID'] = str(_CLAIM.domain_id)
    work = pathlib.Path(tempfile.mkdtemp(prefix='wurde-nav-bench-'))
    maps = [(name, ROOT / 'config' / 'maps' / f'{name}.xml') for name in shipped.split(',') if name]
    chosen = [kind for kind in kinds.split(',') if kind] or list(KINDS)
    unknown = sorted(set(chosen) - set(KINDS))
    if unknown:
        raise SystemExit(f'bench: no map kind {", ".join(unknown)} (kinds: {", ".join(KINDS)})')
    for i in range(generated):
        kind = chosen[i % len(chosen)]
        path = work / f'generated-{kind}-{seed + i}.xml'
        save_map(random_map(seed + i, kind), path)
        maps.append((f'generated {kind} #{seed + i}', path))
    return work, maps


def _start_of(map_file: pathlib.Path) -> tuple[float, float, float]:
    from wurde_idl.mapfile import load_map_data
    place = load_map_data(map_file).places['start']
    return place.x, place.y, place.theta


def row(result: RunResult) -> str:
    p, d, o = result.pose, result.dead_reckoning, result.odometry
    recovered = 'never' if p.recovered_after_m is None else f'{p.recovered_after_m:.1f}'
    return (f'| {result.name} | {result.driven_m:.0f} | {"yes" if result.reached else "NO"} | '
            f'{p.position_rmse * 100:.1f} | {p.heading_rmse_deg:.2f} | {p.position_max * 100:.1f} | {recovered} | '
            f'{d.position_rmse * 100:.1f} | {o.position_rmse * 100:.1f} | {result.seconds:.0f} |')


HEADER = ('| run | driven m | route done | Pose RMSE cm | Pose heading RMSE deg | Pose max cm | recovered after m '
          '| dead reckoning RMSE cm | odometry alone RMSE cm | wall s |\n|' + '---|' * 10)


if __name__ == '__main__':
    sys.exit('nav_run.py is a library; run bench/nav_accuracy.py')
