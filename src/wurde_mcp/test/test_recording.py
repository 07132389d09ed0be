"""record and replay (wurde_mcp.recording) with real processes: a WURDE stream recorded to one MCAP
file is decodable by another MCAP reader (mcap_ros2) with its full definition, its latched info is
kept as transient local in rosbag2's ``offered_qos_profiles``, which an independent rosbag2 reader
(rosbags) reads, and replayed onto its topic it reaches a WURDE consumer again, message for
message; the definition of a type includes every type it uses once.  (Bag directories:
test_record_bag_directory.py; bags of other writers: test_replay_bags.py.)"""

from __future__ import annotations

import os
import pathlib
import re
import signal
import time

import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from wurde_core import CommsManager, Pose3D, topic
from wurde_core.interfaces import LocalizationPose
from wurde_mcp.recording import message_definition
from wurde_testing import ChildProcess, find_executable

from rosbag2_schema import check_bagfile_information, check_profile

STREAM = 'Localization/Dead-Reckoning'
COUNT = 30
DEADLINE = 30.0


def _until(predicate, what: str, manager: CommsManager, child: ChildProcess | None = None) -> None:
    deadline = time.monotonic() + DEADLINE
    while not predicate():
        assert child is None or child.process.poll() is None, f'{what}: the child exited: {child.stderr}'
        assert time.monotonic() < deadline, f'{what}: not within {DEADLINE} s'
        manager.step()
        manager.wait(0.05)


def test_a_definition_names_each_type_it_uses_once(ros_domain: int) -> None:
    text = message_definition('wurde_interfaces/msg/LocalizationPoseData')
    assert text.startswith('# Data (publish section) of WURDE interface LocalizationPose')
    assert text.count('MSG: wurde_interfaces/msg/Header') == 1 and text.count('MSG: wurde_interfaces/msg/Pose3D') == 1
    assert 'MSG: builtin_interfaces/msg/Time' in text                     # through the header's stamp


def test_a_stream_recorded_to_mcap_is_decodable_and_replays_onto_its_topic(ros_domain: int,
                                                                         tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'run.mcap'
    supplier = CommsManager('Recorded')
    supplier.set_no_sleep()
    pose = LocalizationPose(STREAM)
    supplier.register_supplier(pose)
    try:
        pose.info.cmd_flags.set_value(7)
        pose.publish_info()
        with ChildProcess([find_executable('wurde_mcp', 'record'), '-o', str(path), '-t', '^/wurde/']) as record:
            record.expect('record ready', timeout=60)
            _until(lambda: pose.peers('data') > 0 and f'record: {topic(STREAM, "info")}' in record.stdout,
                   'the recorder subscribed', supplier, record)
            for i in range(1, COUNT + 1):
                pose.data.pose = Pose3D(float(i), 0.5, 0.0, 0.1, 0.0, 0.0)
                assert pose.publish_data()
                assert pose.wait_delivered(DEADLINE), f'message {i} not acknowledged by the recorder'
            record.process.send_signal(signal.SIGINT)
            assert record.process.wait(timeout=DEADLINE) == 0, record.stderr
            record.expect('messages on', timeout=DEADLINE)             # the file was finished
    finally:
        supplier.clean_up()

    # Any MCAP reader decodes it: mcap_ros2 with the stored definitions.
    with open(path, 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        decoded = [(channel.topic, msg) for _, channel, _, msg in reader.iter_decoded_messages()]
    data = [msg for name, msg in decoded if name == topic(STREAM, 'data')]
    assert [round(m.pose.x) for m in data] == list(range(1, COUNT + 1))
    assert data[0].pose.y == 0.5 and data[0].header.source == 'Recorded'
    info = [msg for name, msg in decoded if name == topic(STREAM, 'info')]
    assert info and info[-1].cmd_flags == 7
    with open(path, 'rb') as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        rosbag2 = [m for m in reader.iter_metadata() if m.name == 'rosbag2']
    channels = {c.topic: c for c in summary.channels.values()}
    # rosbag2's channel metadata, and nothing of its own.
    assert all(set(c.metadata) == {'offered_qos_profiles', 'topic_type_hash'} for c in channels.values())
    offers = yaml.safe_load(channels[topic(STREAM, 'info')].metadata['offered_qos_profiles'])
    for k, profile in enumerate(offers):
        check_profile(profile, f'offered_qos_profiles[{k}]')
    assert [p['durability'] for p in offers] == ['transient_local'] and offers[0]['reliability'] == 'reliable'
    assert yaml.safe_load(channels[topic(STREAM, 'data')].metadata['offered_qos_profiles'])[0]['durability'] \
        == 'volatile'
    assert channels[topic(STREAM, 'data')].metadata['topic_type_hash'].startswith('RIHS01_')
    assert summary.schemas[channels[topic(STREAM, 'data')].schema_id].name == \
        'wurde_interfaces/msg/LocalizationPoseData'
    # The bag's metadata as rosbag2's MCAP storage writes it (what ``ros2 bag info FILE`` reads).
    assert len(rosbag2) == 1
    information = yaml.safe_load(rosbag2[0].metadata['serialized_metadata'])
    check_bagfile_information(information)
    assert information['relative_file_paths'] == [path.name]
    # An independent rosbag2 reader gets every message and the QoS.
    with Reader(path) as bag:
        counts = {c.topic: c.msgcount for c in bag.connections}
        durability = {c.topic: [q.durability.name for q in c.ext.offered_qos_profiles] for c in bag.connections}
        assert sum(1 for _ in bag.messages()) == bag.message_count
    assert counts[topic(STREAM, 'data')] == COUNT and durability[topic(STREAM, 'info')] == ['TRANSIENT_LOCAL']

    # Replayed onto the data topic, a WURDE consumer hears every pose in order.
    listener = CommsManager('Replayed')
    listener.set_no_sleep()
    heard = LocalizationPose(STREAM)
    heard.set_queue_mode(True)
    listener.register_consumer(heard)
    xs: list[int] = []

    def take() -> bool:
        while heard.get_next_data():
            xs.append(round(heard.data.pose.x()))
        return len(xs) >= COUNT

    try:
        listener.step()
        # Only the stream's data topic: the recording also holds whatever else matched ^/wurde/,
        # e.g. a heartbeat beat of this process's managers when the recording took longer than a
        # beat interval on a loaded machine (r42 replayed 31 messages from 2 topics).
        only = f'^{re.escape(topic(STREAM, "data"))}$'
        with ChildProcess([find_executable('wurde_mcp', 'replay'), str(path), '-t', only, '-r', '4'],
                          env=dict(os.environ)) as replay:
            _until(take, 'the replayed poses', listener, None)
            assert replay.process.wait(timeout=DEADLINE) == 0, replay.stderr
            replay.expect(f'replay: {COUNT} messages', timeout=DEADLINE)
            assert 'replay: 1 topics' in replay.stdout, replay.stdout
        assert xs == list(range(1, COUNT + 1))
    finally:
        listener.clean_up()
