"""The CARMEN log reader (pluto_nav.logs.carmen): every message type of CARMEN's logger, CARMEN's
conventions (beam angles guessed from the count, no-return, mounts), and bad input counted with
file and line, never a traceback.  Small logs written here; the real benchmark logs only in the
last test, skipped when /work/shared/data/slam-benchmark is not there.  No ROS."""

from __future__ import annotations

import gzip
import math
import pathlib
import re
import time

import numpy as np
import pytest

from pluto_nav.logs import LogError, LogProblems, OdometryRecord, ParamRecord, ScanRecord, TruePoseRecord, load_log
from pluto_nav.logs.carmen import read_carmen
from pluto_nav.logs.carmen_messages import guess_angle_increment, guess_fov

from carmen_scene import DEG, flaser, odom, rawlaser, robotlaser, tail, write

BENCHMARK = pathlib.Path('/work/shared/data/slam-benchmark')


def read(path: pathlib.Path) -> tuple[list, LogProblems, list[str]]:
    warnings: list[str] = []
    problems = LogProblems(warnings.append)
    return list(read_carmen(path, problems)), problems, warnings


def test_carmen_guesses_the_fan_of_old_laser_lines_as_carmen_does() -> None:
    # readlog.c's carmen_laser_guess_fov / carmen_laser_guess_angle_increment, value by value.
    assert guess_fov(181) == pytest.approx(math.pi) and guess_angle_increment(181) == pytest.approx(DEG)
    assert guess_fov(180) == pytest.approx(179 * DEG) and guess_angle_increment(180) == pytest.approx(DEG)
    assert guess_fov(361) == pytest.approx(math.pi) and guess_angle_increment(361) == pytest.approx(0.5 * DEG)
    assert guess_fov(360) == pytest.approx(179.5 * DEG) and guess_angle_increment(360) == pytest.approx(0.5 * DEG)
    assert guess_fov(401) == pytest.approx(100 * DEG) and guess_angle_increment(401) == pytest.approx(0.25 * DEG)
    assert guess_angle_increment(400) == pytest.approx(0.25 * DEG)
    assert guess_fov(100) == pytest.approx(math.pi) and guess_angle_increment(100) == pytest.approx(math.pi / 99)


def test_every_message_type_is_read_with_carmens_field_order(tmp_path: pathlib.Path) -> None:
    ranges = [1.0, 2.0, 81.91, 80.0, 0.0, -1.0, float('nan'), 3.5]
    lines = [
        '# CARMEN Logfile', '# message formats defined: PARAM SYNC ODOM FLASER ...',
        'PARAM robot_frontlaser_offset 0.25 0.0 testhost 0.0',
        'PARAM robot_rearlaser_offset 0.1 0.0 testhost 0.0',
        'PARAM map_comment a value with spaces 0.0 testhost 0.0',
        'SYNC tag1 1.0 testhost 0.0',
        odom(1.0, 1.0, 2.0, 0.5, tv=0.3, rv=-0.1),
        flaser(1.1, 360, robot=(1.0, 2.0, 0.5)),
        flaser(1.2, ranges, robot=(1.0, 2.0, 0.5), name='RLASER'),
        robotlaser(1.3, [1.0, 2.0, 60.0], laser=(1.2, 2.0, 0.0), robot=(1.0, 2.0, 0.0), remissions=[5.0, 6.0, 7.0]),
        robotlaser(1.4, [1.0, 2.0], laser=(0.9, 2.0, math.pi), robot=(1.0, 2.0, 0.0), number=2,
                   resolution=-DEG, with_mode=False),
        rawlaser(1.5, [1.0, 2.0, 3.0], 3, remissions=[1.0, 2.0, 3.0]),
        'TRUEPOS 1.0 2.0 0.5 1.1 2.1 0.6 ' + tail(1.6),
        'LASER4 3 1.0 2.0 3.0 ' + tail(1.7),
        'REMISSIONFLASER 2 1.0 10.0 2.0 20.0 ' + tail(1.8),
    ]
    records, problems, warnings = read(write(tmp_path / 'all.clf', lines))
    assert not problems and not warnings, (problems.summary(), warnings)
    assert problems.ignored['SYNC line'] == 1
    params = [r for r in records if isinstance(r, ParamRecord)]
    assert [(p.name, p.value) for p in params] == [('robot_frontlaser_offset', '0.25'),
                                                    ('robot_rearlaser_offset', '0.1'),
                                                    ('map_comment', 'a value with spaces')]
    o = next(r for r in records if isinstance(r, OdometryRecord))
    assert (o.stamp, o.pose, o.tv, o.rv) == (1.0, (1.0, 2.0, 0.5), 0.3, -0.1)
    assert o.origin == f'{tmp_path / "all.clf"}:7'
    truth = next(r for r in records if isinstance(r, TruePoseRecord))
    assert truth.true_pose == (1.0, 2.0, 0.5) and truth.odometry == (1.1, 2.1, 0.6) and truth.stamp == 1.6
    scans = {s.stamp: s for s in records if isinstance(s, ScanRecord)}
    assert [scans[t].channel for t in sorted(scans)] == ['front', 'rear', 'front', 'rear', 'raw3', 'raw4', 'raw1']
    front = scans[1.1]                     # 360 readings: -90 .. +89.5 degrees, half a degree apart
    assert len(front.ranges) == 360 and front.stamp == 1.1
    assert front.angles[0] == pytest.approx(-90 * DEG) and front.angles[-1] == pytest.approx(89.5 * DEG)
    assert front.odometry == (1.0, 2.0, 0.5) and front.laser_pose == (1.0, 2.0, 0.5)
    assert front.config.max_range == 80.0 and front.config.mount == pytest.approx((0.25, 0.0, 0.0))
    rear = scans[1.2]                      # no-return: >= max range, 81.91, NaN -> inf; <= 0 -> NaN
    np.testing.assert_array_equal(rear.ranges, [1.0, 2.0, math.inf, math.inf, math.nan, math.nan, math.inf, 3.5])
    assert rear.config.angular_resolution == pytest.approx(math.pi / 7)
    assert rear.config.mount == pytest.approx((-0.1, 0.0, math.pi))        # behind the centre, backwards
    robot1 = scans[1.3]
    assert robot1.channel == 'front' and robot1.config.max_range == 50.0
    np.testing.assert_array_equal(robot1.ranges, [1.0, 2.0, math.inf])
    np.testing.assert_array_equal(robot1.remissions, [5.0, 6.0, 7.0])
    assert robot1.config.mount == pytest.approx((0.2, 0.0, 0.0), abs=1e-6)  # relative(robot, laser)
    robot2 = scans[1.4]
    # A clockwise fan (negative resolution), written without remission_mode (CARMEN before 2006):
    # turned into counter-clockwise order.
    assert robot2.channel == 'rear' and robot2.config.angular_resolution == pytest.approx(DEG, abs=1e-6)
    assert robot2.config.start_angle == pytest.approx(-math.pi / 2 - DEG, abs=1e-5)
    np.testing.assert_array_equal(robot2.ranges, [2.0, 1.0])
    assert robot2.config.mount[:2] == pytest.approx((-0.1, 0.0), abs=1e-6)
    assert math.cos(robot2.config.mount[2]) == pytest.approx(-1.0)      # facing backwards
    raw3 = scans[1.5]
    assert raw3.odometry is None and raw3.config.start_angle == pytest.approx(-math.pi / 2, abs=1e-6)
    np.testing.assert_array_equal(raw3.remissions, [1.0, 2.0, 3.0])
    assert scans[1.7].config.angular_resolution == pytest.approx(math.pi / 2)
    np.testing.assert_array_equal(scans[1.8].ranges, [1.0, 2.0])
    np.testing.assert_array_equal(scans[1.8].remissions, [10.0, 20.0])
    assert scans[1.8].config.mount == pytest.approx((0.25, 0.0, 0.0))   # laser 1 is the front laser


def test_gzip_and_plain_give_the_same_records(tmp_path: pathlib.Path) -> None:
    lines = [odom(1.0 + 0.1 * i, x=0.01 * i) for i in range(20)] + [flaser(1.05 + 0.2 * i, 181) for i in range(10)]
    plain, _, _ = read(write(tmp_path / 'a.clf', lines))
    packed, problems, _ = read(write(tmp_path / 'a.clf.gz', lines, compress=True))
    assert not problems and len(plain) == len(packed) == 30
    for a, b in zip(plain, packed):
        assert type(a) is type(b) and a.stamp == b.stamp
    log = load_log(tmp_path / 'a.clf.gz')
    assert len(log.scans) == 10 and len(log.odometry) == 20 and log.odometry_source == 'odometry records'


def test_without_odom_lines_the_odometry_comes_from_the_laser_lines(tmp_path: pathlib.Path) -> None:
    path = write(tmp_path / 'csail.clf', [flaser(5.0 + i, 361, robot=(i, 0.0, 0.1)) for i in range(4)])
    log = load_log(path)
    assert log.odometry_source == 'the laser lines'
    assert [o.pose for o in log.odometry] == [(float(i), 0.0, 0.1) for i in range(4)]
    assert log.scans[0].angles[-1] == pytest.approx(90 * DEG)


def test_bad_lines_are_counted_and_warned_once_per_kind_with_file_and_line(tmp_path: pathlib.Path) -> None:
    good = [odom(1.0), flaser(1.0, 10)]
    lines = [
        *good,
        'ODOM 1.0 2.0',                                    # 3: too few fields
        'ODOM 1.0 2.0',                                    # 4: again: counted, not warned again
        flaser(2.0, 10).replace('FLASER 10 ', 'FLASER 12 '),   # 5: num_readings larger than what follows
        odom(2.0).replace('ODOM 0.000000', 'ODOM abc'),    # 6: not a number
        odom(2.1).replace('ODOM 0.000000', 'ODOM nan'),    # 7: non-finite pose
        'GPS 1 2 3 ' + tail(2.2),                          # 8: a type this reader does not know
        'GPS 1 2 3 ' + tail(2.3),                          # 9
        'NMEAGGA 1 2 3 ' + tail(2.4),                      # 10: another unknown type: its own warning
        flaser(2.5, 10).replace('FLASER 10 ', 'FLASER 8 '),    # 11: fewer readings than the count says? extra fields
        odom(3.0),                                         # 12
        odom(2.0),                                         # 13: 1 s back: reordered
        odom(-10.0),                                       # 14: 13 s back: dropped
        'ROBOTLASER1 0 -1.57 3.14 0.0174 50 0.01 0 5 1 2',  # 15: cut inside the readings
        'PARAM robot_frontlaser_offset abc 0.0 testhost 0.0',  # 16: kept, but no mount
    ]
    path = write(tmp_path / 'bad.clf', lines)
    raw = path.read_bytes() + b'ODOM \x00\x01\x02 binary\n' + b'ODOM \xff\xfe 1 2\n' + odom(4.0).encode() + b'\n'
    path.write_bytes(raw)
    records, problems, warnings = read(path)
    counts = problems.counts
    assert counts['truncated ODOM line'] == 2
    assert counts['truncated FLASER line'] == 1
    assert counts['malformed FLASER line'] == 1
    assert counts['ODOM line with a field that is not a number'] == 1
    assert counts['ODOM line with a non-finite pose'] == 1
    assert counts['unsupported message type GPS'] == 2 and counts['unsupported message type NMEAGGA'] == 1
    assert counts['reordered'] == 1 and counts['odometry record far back in time'] == 1
    assert counts['truncated ROBOTLASER1 line'] == 1
    assert counts['line that is not text'] == 2
    assert counts['PARAM laser mount that is not a number (ignored)'] == 1
    assert any(isinstance(r, ParamRecord) and r.value == 'abc' for r in records)
    assert len(warnings) == len(counts)             # one warning per kind
    assert any(w.startswith(f'{path}:3: truncated ODOM line') for w in warnings), warnings
    assert any(w.startswith(f'{path}:13: reordered') for w in warnings), warnings
    assert any(w.startswith(f'{path}:17: line that is not text') for w in warnings), warnings
    stamps = [r.stamp for r in records if isinstance(r, OdometryRecord)]
    assert stamps == [1.0, 2.0, 3.0, 4.0]           # the late one put in its place, the far one gone
    summary = problems.summary()
    assert '2 unsupported message type GPS' in summary and '1 reordered' in summary


def test_a_cut_gzip_stream_keeps_the_records_before_the_cut(tmp_path: pathlib.Path) -> None:
    lines = [odom(1.0 + 0.01 * i, x=0.001 * i) for i in range(3000)]
    whole = gzip.compress(('\n'.join(lines) + '\n').encode())
    cut = tmp_path / 'cut.clf.gz'
    cut.write_bytes(whole[:len(whole) // 2])
    warnings: list[str] = []
    log = load_log(cut, warn=warnings.append)
    assert 0 < len(log.odometry) < 3000
    assert len(log.problems.errors) == 1 and log.problems.errors[0] == warnings[0]
    last = len(log.odometry)
    assert log.problems.errors[0].startswith(f'{cut}: the gzip stream is damaged after line {last} ')
    assert [o.x for o in log.odometry] == pytest.approx([0.001 * i for i in range(last)])
    damaged = bytearray(whole)
    for i in range(len(whole) // 2, len(whole) // 2 + 64):
        damaged[i] ^= 0x5A
    broken = tmp_path / 'broken.clf.gz'
    broken.write_bytes(bytes(damaged))
    log = load_log(broken, warn=lambda _: None)
    assert len(log.problems.errors) == 1 and 'gzip stream is damaged after line' in log.problems.errors[0]
    assert 0 < len(log.odometry) < 3000


def test_files_with_nothing_usable_are_refused_naming_the_file(tmp_path: pathlib.Path) -> None:
    empty = write(tmp_path / 'empty.clf', [])
    empty.write_bytes(b'')
    with pytest.raises(LogError, match=f'^{re.escape(str(empty))}: an empty file$'):
        load_log(empty)
    packed_empty = tmp_path / 'empty.clf.gz'
    packed_empty.write_bytes(gzip.compress(b''))
    with pytest.raises(LogError, match=f'^{re.escape(str(packed_empty))}: '):
        load_log(packed_empty)
    comments = write(tmp_path / 'comments.clf', ['# nothing but', '# comments', 'PARAM a b 0.0 h 0.0'])
    with pytest.raises(LogError, match=f'^{re.escape(str(comments))}: no usable record'):
        load_log(comments)
    unusable = write(tmp_path / 'unusable.clf', ['ODOM 1 2', 'GPS 1 2 3 ' + tail(1.0)])
    with pytest.raises(LogError, match=r'no usable record.*1 truncated ODOM line'):
        load_log(unusable, warn=lambda _: None)
    binary = tmp_path / 'binary.clf'
    binary.write_bytes(bytes(range(256)) * 10)
    with pytest.raises(LogError, match=f'^{re.escape(str(binary))}: neither a CARMEN log'):
        load_log(binary)
    with pytest.raises(LogError, match=f'^{re.escape(str(tmp_path / "missing.clf"))}: cannot be read'):
        load_log(tmp_path / 'missing.clf')


def test_a_first_line_longer_than_the_sniffed_sample_is_still_a_carmen_log(tmp_path: pathlib.Path) -> None:
    ranges = [2.0] * 12000                    # a 1081-beam ROBOTLASER1 is ~8 kB; this one ~70 kB
    path = write(tmp_path / 'long.log', [robotlaser(1.0, ranges, laser=(0, 0, 0), robot=(0, 0, 0))])
    log = load_log(path)
    assert len(log.scans) == 1 and len(log.scans[0].ranges) == 12000


def test_a_log_of_fr079s_size_reads_fast(tmp_path: pathlib.Path) -> None:
    lines = []
    for i in range(1500):
        lines += [odom(1.0 + 0.2 * i + 0.05 * k, x=0.01 * i) for k in range(3)] + [flaser(1.0 + 0.2 * i + 0.01, 360)]
    path = write(tmp_path / 'big.clf.gz', lines, compress=True)
    start = time.perf_counter()
    log = load_log(path)
    elapsed = time.perf_counter() - start
    assert len(log.scans) == 1500 and len(log.odometry) == 4500
    assert elapsed < 3.0, f'{elapsed:.2f} s for 6000 lines (FR079 reads in ~0.15 s)'


@pytest.mark.skipif(not BENCHMARK.is_dir(), reason='the benchmark logs are not on this machine')
def test_the_benchmark_logs() -> None:
    fr079 = load_log(BENCHMARK / 'fr079.clf.gz')
    assert len(fr079.scans) == 1464 and {len(s.ranges) for s in fr079.scans} == {360}
    assert len(fr079.odometry) == 4948 and fr079.odometry_source == 'odometry records'
    assert not fr079.problems
    csail = load_log(BENCHMARK / 'mit-csail.clf.gz')
    assert len(csail.scans) == 1988 and {len(s.ranges) for s in csail.scans} == {361}
    assert len(csail.odometry) == 1988 and csail.odometry_source == 'the laser lines'
    assert np.isinf(csail.scans[0].ranges).sum() > 0 and not np.isnan(csail.scans[0].ranges).any()
