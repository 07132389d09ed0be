"""People in the running simulator, real processes: a person walking into a standing robot presses
a bumper of a real dummy_base, which logs each contact once; a real dummy_sick's scans show a person
where the base's truth topic says it is (two processes, each computing the people from the stamp
alone); and ``record`` takes the people's truth into the run's MCAP."""

from __future__ import annotations

import json
import math
import os
import pathlib
import re
import signal

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from people_fixture import BASE, PEOPLE_TOPIC, ROBOT_RADIUS, START, Truth, people_config
from sim_fixture import MAPS, Observer
from wurde_core.heartbeat import RESTART_ENV
from wurde_core.resume import STATE_ENV
from wurde_core.ros_adaptor import take_stamped
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.sim.mapfile import load_map

WAIT_S = 90.0
#: The bumpers feel 1 cm beyond the footprint (BumperRing.contact_margin).
REACH = ROBOT_RADIUS + 0.01


def subscribe(observer: Observer, message_type: type, topic: str) -> object:
    return observer.manager.node.create_subscription(message_type, topic, lambda _: None, 100)


def base_process(path: pathlib.Path, **env: str) -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(path), '-n', BASE],
                        env=dict(os.environ, **env))


def test_a_person_walking_into_a_standing_robot_presses_its_bumper_and_counts_once(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The robot stands in the corridor at (4.8, 7.5) facing east — where a restart of its base
    left it (wurde_core.resume: a restarted base puts the robot back where it stood), since no
    walk may cross the config's start.  Walker goes up and down the corridor 0.1 m ahead of its
    centre: each pass presses the front bumper, and the base logs the contact once."""
    from visualization_msgs.msg import Marker, MarkerArray
    path, _ = people_config(tmp_path, ['<person name="walker" points="4.9,6.8 4.9,8.2" speed="1.0" '
                                       'pause="0.5" mode="back-and-forth" radius="0.25" height="1.7"/>'])
    state = tmp_path / f'{BASE}.resume'
    state.write_text(json.dumps({'x': 4.8, 'y': 7.5, 'theta': 0.0}))
    observer = Observer({f'{BASE}Bumpers': 'Bumper', f'{BASE}Truth': 'Egomotion'})
    markers = subscribe(observer, MarkerArray, PEOPLE_TOPIC)
    truth = Truth()

    def contacts(text: str) -> list[int]:
        """The contacts the base's Logger wrote (its own lines; rclpy's log repeats them)."""
        return [int(n) for n in re.findall(r'^\[WARN\] PlutoBase: person "walker" touched the robot '
                                           r'\(bumper front\); contact (\d+) with people$', text, re.M)]
    def onsets(o: Observer) -> list[int]:
        """Indices of the Bumper events where a bumper became pressed."""
        events = o.events[f'{BASE}Bumpers']
        return [i for i in range(1, len(events)) if events[i][1].bumped and not events[i - 1][1].bumped]
    try:
        with base_process(path, **{STATE_ENV: str(state), RESTART_ENV: '1'}) as base:
            def two_contacts(o: Observer) -> bool:
                for message, _ in take_stamped(markers):
                    truth.add(message)
                return len(onsets(o)) >= 2 and len(truth.stamps) > 20
            observer.until(two_contacts, 'two passes of the walker pressing the bumper', WAIT_S)
            assert 'resumed: restart 1' in base.stderr
            assert base.stop(timeout=30) == 0
        counted = contacts(base.stderr)
        assert len(counted) >= 2 and counted == list(range(1, len(counted) + 1))   # each logged once
        assert f'[NOTICE] {BASE}: {len(counted)} contacts with people' in base.stderr
        # The robot stood where it was put, never pushed.
        assert {(m.location.x, m.location.y) for _, m in observer.events[f'{BASE}Truth']} == {(4.8, 7.5)}
        events = observer.events[f'{BASE}Bumpers']
        assert all(list(message.bumpers) in ([True, False], [False, False]) for _, message in events)
        checked = 0
        for i in onsets(observer):
            # Pressed as the truth topic has the walker reach the robot, not before.
            before, now = (truth.at('walker', events[j][0]) for j in (i - 1, i))
            if before is None or now is None:
                continue                                     # before the truth's first message
            assert math.dist(now, (4.8, 7.5)) - 0.25 <= REACH + 1e-3
            assert math.dist(before, (4.8, 7.5)) - 0.25 > REACH - 1e-3
            checked += 1
        assert checked >= 1
        marker = truth.markers[-1]
        assert (marker.ns, marker.id, marker.text, marker.type, marker.header.frame_id) == \
            ('people', 0, 'walker', Marker.CYLINDER, 'map')
        assert (marker.scale.x, marker.scale.y, marker.scale.z, marker.pose.position.z) == \
            pytest.approx((0.5, 0.5, 1.7, 0.85))
        assert marker.pose.position.x == pytest.approx(4.9)
        assert np.diff(truth.stamps) == pytest.approx(0.1, abs=1e-6)   # the odometry rate, 10 Hz
    finally:
        observer.close()


def _circle_range(origin: np.ndarray, angles: np.ndarray, centre: tuple[float, float],
                  radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Each beam's range to a circle (inf: a miss), and how far its line passes from the edge."""
    direction = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    offset = np.asarray(centre) - origin
    along = direction @ offset
    across = np.abs(direction[:, 0] * offset[1] - direction[:, 1] * offset[0])
    inside = radius ** 2 - across ** 2
    hit = (inside >= 0.0) & (along > 0.0)
    ranges = np.where(hit, along - np.sqrt(np.where(hit, inside, 0.0)), np.inf)
    return ranges, np.abs(across - radius)


def test_the_lasers_scans_show_a_person_where_the_truth_topic_says(ros_domain: int,
                                                                    tmp_path: pathlib.Path) -> None:
    """Crosser walks across the corridor 2.8 m ahead of the laser, pausing 2 s at each side.  Each
    scan is compared beam by beam with the walls plus a disc where the base's truth messages
    (interpolated to the scan's centre stamp) put the person: within the 1 cm quantisation while
    the person stands, and within what 0.1 s of walking at 0.4 m/s can blur while it walks."""
    from sensor_msgs.msg import LaserScan
    from visualization_msgs.msg import MarkerArray
    path, _ = people_config(tmp_path, ['<person name="crosser" points="6,6.8 6,8.2" speed="0.4" '
                                       'pause="2" mode="back-and-forth" radius="0.25" height="1.7"/>'])
    office = load_map(MAPS / 'office.xml')
    origin = np.array([START[0] + 0.2, START[1]])          # config/sim's laser: 0.2 m ahead
    angles = np.radians(np.arange(361) * 0.5 - 90.0)
    walls = office.raycast(origin, angles, max_range=81.82)
    observer = Observer({f'{BASE}Truth': 'Egomotion'})
    markers = subscribe(observer, MarkerArray, PEOPLE_TOPIC)
    scans = subscribe(observer, LaserScan, '/PlutoLaser/scan')
    truth = Truth()
    pending: list[object] = []
    compared = {'standing': 0, 'walking': 0}

    def compare(o: Observer) -> bool:
        for message, _ in take_stamped(markers):
            truth.add(message)
        pending.extend(message for message, _ in take_stamped(scans))
        while pending:
            scan = pending[0]
            stamp = scan.header.stamp.sec + scan.header.stamp.nanosec * 1e-9
            if truth.stamps and truth.stamps[-1] <= stamp:
                break                                       # its truth is still to come
            pending.pop(0)
            found = truth.bracket('crosser', stamp)
            if found is None:
                continue
            standing = found[0] == found[1]
            centre = truth.at('crosser', stamp)
            person, edge = _circle_range(origin, angles, centre, 0.25)
            # Walking, the interpolated truth may be 4 cm off (0.1 s at 0.4 m/s, where a pause
            # begins or ends between two truth messages): beams within 10 cm of the person's
            # edge, which 4 cm can move on or off it (or lengthen steeply), are not compared.
            tolerance, margin = (0.006, 0.006) if standing else (0.05, 0.1)
            clear = edge > margin
            expected = np.minimum(walls, person)
            got = np.array(scan.ranges)
            on_person = clear & np.isfinite(person)
            assert on_person.sum() >= 5, 'the person is in the scan'
            assert np.abs(got[clear] - expected[clear]).max() <= tolerance, \
                f'{"standing" if standing else "walking"} at {centre}: scan and truth disagree'
            compared['standing' if standing else 'walking'] += 1
        return compared['standing'] >= 3 and compared['walking'] >= 10

    try:
        with base_process(path), ChildProcess([find_executable('wurde_drivers', 'dummy_sick'), '-c', str(path),
                                               '-n', 'PlutoLaser']):
            observer.until(compare, 'scans compared while the person stands and walks', WAIT_S)
        assert {(m.location.x, m.location.y) for _, m in observer.events[f'{BASE}Truth']} == {START[:2]}
    finally:
        observer.close()


def test_record_takes_the_peoples_truth_into_the_mcap(ros_domain: int, tmp_path: pathlib.Path) -> None:
    path, _ = people_config(tmp_path, ['<person name="ana" points="6,6.8 6,8.2" radius="0.25"/>',
                                       '<person name="trolley" points="9,7 12,7" length="0.9" width="0.6" '
                                       'height="1.0" speed="0.6"/>'])
    recording = tmp_path / 'people.mcap'
    record_argv = [find_executable('wurde_mcp', 'record'), '-o', str(recording), '-t', 'ground_truth']
    with base_process(path) as base, ChildProcess(record_argv) as record:
        record.expect(f'record: {PEOPLE_TOPIC}: first message', timeout=WAIT_S)
        assert base.process.poll() is None, base.stderr
        record.process.send_signal(signal.SIGINT)
        assert record.process.wait(timeout=WAIT_S) == 0, record.stderr
    with open(recording, 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        people = [msg for _, channel, _, msg in reader.iter_decoded_messages() if channel.topic == PEOPLE_TOPIC]
    assert people, 'no people in the recording'
    assert [m.text for m in people[-1].markers] == ['ana', 'trolley']
    trolley = people[-1].markers[1]
    assert (trolley.scale.x, trolley.scale.y, trolley.scale.z) == pytest.approx((0.9, 0.6, 1.0))
    assert 9.0 <= trolley.pose.position.x <= 12.0 and trolley.pose.position.y == pytest.approx(7.0)
