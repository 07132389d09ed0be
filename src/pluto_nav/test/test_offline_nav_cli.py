"""offline_nav on recordings: a CARMEN log of the simulated robot (noise on, a generated map) for
SLAM, its saved map for localization (as XML and as a CARMEN map), the FR079 excerpt as a rosbag2 MCAP
(carmen_log convert), scored with relations; and what a user gets for files that are wrong: one line, exit status 2."""

from __future__ import annotations

import gzip
import math
import pathlib

import numpy as np
import pytest
import random_maps
import slam_sim
from carmen_scene import flaser, odom, write
from nav_sim import MOUNT

from pluto_nav.carmen_log import main as carmen_log
from pluto_nav.geometry import compose, inverse, relative
from pluto_nav.offline_nav import main as offline_nav
from pluto_nav.slam_metric import load_trajectory
from wurde_idl.gridmap import load_grid_map
from wurde_idl.mapfile import load_map_data
from wurde_testing.carmen_maps import carmen_map_bytes

DATA = pathlib.Path(__file__).resolve().parent / 'data'


def _simulated_log(tmp_path: pathlib.Path, seed: int) -> tuple[pathlib.Path, pathlib.Path, dict[float, np.ndarray]]:
    """A CARMEN log (ODOM and FLASER lines, 361 beams) of a loop in generated map ``seed``, its
    relations from the simulator's truth as the benchmark's are made (consecutive scans, and scans
    of the same place 30 s or more apart), and the true robot poses."""
    world = random_maps.random_map(seed)
    route = slam_sim.loop_route(world, 25.0, np.random.default_rng(seed))
    lines, truth = [], {}
    for k, scan in enumerate(slam_sim.drive(world, route, seed=seed)):
        stamp = 2000.0 + 0.2 * k
        robot = compose(scan.truth, inverse(MOUNT))
        laser = compose(scan.odometry, MOUNT)            # the line's laser pose: the mount it implies
        ranges = [r if math.isfinite(r) else 81.91 for r in scan.ranges]
        lines += [odom(stamp, *scan.odometry), flaser(stamp, ranges, robot=scan.odometry, laser=tuple(laser))]
        truth[round(stamp, 6)] = robot
    log = write(tmp_path / 'sim.clf.gz', lines, compress=True)
    stamps = sorted(truth)
    relations = tmp_path / 'sim.relations'
    pairs = list(zip(stamps, stamps[1:]))
    pairs += [(a, b) for a in stamps[::5] for b in stamps[::7]
              if b - a > 30.0 and math.dist(truth[a][:2], truth[b][:2]) < 2.0]
    with open(relations, 'w') as out:
        for a, b in pairs:
            d = relative(truth[a], truth[b])
            out.write(f'{a:.6f} {b:.6f} {d[0]:.6f} {d[1]:.6f} 0 0 0 {d[2]:.6f}\n')
    return log, relations, truth


def _scores(text: str) -> tuple[float, float]:
    """The translational errors printed for ours and for the odometry."""
    ours = float(text.split('ours:')[1].split('translation ')[1].split(' m')[0])
    odometry = float(text.split('odometry:')[1].split('translation ')[1].split(' m')[0])
    return ours, odometry


def test_slam_then_localization_on_a_simulated_robot_s_log(tmp_path: pathlib.Path, capsys) -> None:
    log, relations, truth = _simulated_log(tmp_path, 21)
    trajectory, saved = tmp_path / 'slam.tum', tmp_path / 'maps' / 'sim.xml'
    assert offline_nav([str(log), '--slam', '--trajectory', str(trajectory), '--map-out', str(saved),
                        '--relations', str(relations), '--quiet']) == 0
    out = capsys.readouterr().out
    ours, odometry = _scores(out)
    assert ours < 0.02 and ours < odometry / 5, out
    assert 'laser lines' not in out and 'odometry records' in out        # the ODOM lines were used
    stamps, poses = load_trajectory(trajectory)
    assert len(stamps) == len(truth)                                    # one line per scan
    first = truth[round(stamps[0], 6)]
    error = [math.dist(compose(first, relative(poses[0], p))[:2], truth[round(t, 6)][:2])
             for t, p in zip(stamps, poses)]
    assert max(error) < 0.1
    data = load_map_data(saved)                                         # the poseModule's format
    assert len(data.walls) > 20 and 'start' in data.places
    grid = load_grid_map(saved.with_suffix('.yaml'))                    # and map_server's
    assert (grid.cells == 100).sum() > 200
    # Localization in the map just made: the map's start is the odometry's first pose.
    located = tmp_path / 'located.tum'
    assert offline_nav([str(log), '--localize', str(saved), '--trajectory', str(located),
                        '--relations', str(relations), '--quiet']) == 0
    ours, odometry = _scores(capsys.readouterr().out)
    assert ours < 0.03 and ours < odometry / 3
    assert len(load_trajectory(located)[0]) == len(truth)
    # The same grid as a CARMEN map (gzip; CARMEN's maps start at 0, 0: the frame shifts, the
    # relations do not) with its start place: localization in it as well.
    ox, oy, _ = grid.origin
    sx, sy, st = data.places['start']
    probability = np.where(grid.cells < 0, -1.0, grid.cells / 100.0).T
    carmen = tmp_path / 'sim.map.gz'
    carmen.write_bytes(gzip.compress(carmen_map_bytes(probability, grid.resolution,
                                                      places=[(1, 'start', (sx - ox, sy - oy, st))])))
    assert offline_nav([str(log), '--localize', str(carmen), '--trajectory', str(located),
                        '--relations', str(relations), '--quiet']) == 0
    ours, odometry = _scores(capsys.readouterr().out)
    assert ours < 0.03 and ours < odometry / 3


def test_a_rosbag2_bag_of_a_real_robot_beats_its_odometry(tmp_path: pathlib.Path, capsys) -> None:
    bag = tmp_path / 'fr079.mcap'
    assert carmen_log(['carmen_log', 'convert', str(DATA / 'fr079-excerpt.clf.gz'), str(bag)]) == 0
    capsys.readouterr()
    assert offline_nav([str(bag), '--slam', '--relations', str(DATA / 'fr079-excerpt.relations')]) == 0
    captured = capsys.readouterr()
    ours, odometry = _scores(captured.out)
    assert ours < 0.8 * odometry, captured.out
    assert '95 scans' in captured.out and 'graph:' in captured.out
    assert 'scans' in captured.err                                      # progress went to stderr


@pytest.mark.parametrize('write_log, message', [
    (lambda p: None, 'cannot be read'),
    (lambda p: p.write_bytes(b''), 'empty'),
    (lambda p: p.write_text('ODOM 0 0 0 0 0 0 1.0 h 1.0\nODOM 0.1 0 0 0 0 0 1.2 h 1.2\n'), 'no laser scans'),
    (lambda p: p.write_bytes(b'\x89PNG\r\n\x1a\n' + bytes(100)), 'neither a CARMEN log'),
])
def test_a_log_that_cannot_be_used_is_one_line_and_status_2(tmp_path: pathlib.Path, capsys, write_log,
                                                            message: str) -> None:
    path = tmp_path / 'robot.log'
    write_log(path)
    assert offline_nav([str(path), '--slam']) == 2
    err = capsys.readouterr().err
    assert message in err and 'Traceback' not in err and str(path) in err


def test_a_cut_gzip_log_is_used_up_to_the_cut_and_said(tmp_path: pathlib.Path, capsys) -> None:
    whole = (DATA / 'fr079-excerpt.clf.gz').read_bytes()
    cut = tmp_path / 'cut.clf.gz'
    cut.write_bytes(whole[:len(whole) // 2])
    assert offline_nav([str(cut), '--slam', '--quiet']) == 0
    captured = capsys.readouterr()
    assert 'cut.clf.gz' in captured.err and 'Traceback' not in captured.err
    used = int(captured.out.split('scans used ')[1].split()[0])
    assert 10 < used < 95


def test_wrong_arguments_are_refused(tmp_path: pathlib.Path, capsys) -> None:
    log = DATA / 'fr079-excerpt.clf.gz'
    bad_map = tmp_path / 'map.xml'
    bad_map.write_text('<map name="x" version="1.0"><wall x1="0" y1="0" x2="0" y2="0"/></map>')
    assert offline_nav([str(log), '--localize', str(bad_map)]) == 2
    assert 'map.xml:1' in capsys.readouterr().err
    grid = tmp_path / 'grid.yaml'
    grid.write_text('image: none.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n')
    assert offline_nav([str(log), '--localize', str(grid), '--start', '1,2']) == 2
    assert 'none.pgm' in capsys.readouterr().err
    with pytest.raises(SystemExit):
        offline_nav([str(log)])                     # neither --slam nor --localize
    assert gzip.decompress(log.read_bytes())       # the excerpt itself is whole


def test_an_imu_s_heading_is_taken_as_the_localmodule_takes_the_dmu_s() -> None:
    from pluto_nav.logs import ImuRecord, LaserConfig, LogProblems, OdometryRecord, RobotLog, ScanRecord
    from pluto_nav.offline_run import run_offline

    class Still:                          # a method that keeps what it is given: the dead reckoning
        pose, covariance = np.zeros(3), np.eye(3)

        def set_pose(self, pose, covariance) -> None:
            self.pose = np.asarray(pose)

        def predict(self, increment, covariance) -> None:
            self.pose = compose(self.pose, increment)

        def update(self, scan) -> bool:
            return False

    odometry, imu, scans = [], [], []
    config = LaserConfig(-math.pi / 2, math.pi / 360, 30.0)
    for k in range(200):                  # straight ahead at 0.5 m/s; the odometry's heading drifts
        t = 100.0 + 0.05 * k
        drift = 0.1 * (t - 100.0)         # rad
        odometry.append(OdometryRecord(t, 0.025 * sum(math.cos(0.1 * 0.05 * j) for j in range(k)),
                                       0.025 * sum(math.sin(0.1 * 0.05 * j) for j in range(k)), drift))
        imu.append(ImuRecord(t - 0.01, (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 9.8)))
        if k % 4 == 0:
            scans.append(ScanRecord(t, np.full(361, 5.0), config))
    log = RobotLog('synthetic', scans, odometry, 'odometry records', [], imu, {}, {'front': len(scans)},
                   LogProblems())
    with_imu = run_offline(log, Still())
    without = run_offline(log, Still(), imu=False)
    assert abs(with_imu.odometry[-1, 2]) < 1e-6                    # the IMU's heading: none turned
    assert without.odometry[-1, 2] == pytest.approx(0.1 * (log.scans[-1].stamp - 100.0), abs=1e-3)
