"""``record -o DIR``: a WURDE stream recorded to a rosbag2 bag directory, split in several files
(``-b``), whose ``metadata.yaml`` keeps rosbag2 Jazzy's schema (version 9) and its topics' QoS;
an independent rosbag2 reader (rosbags) decodes every message and reads the QoS; ``replay`` of the
directory gives a WURDE consumer every pose in order and the latched info, which it can only get
from a transient-local publisher.  Wrong uses are refused before anything is recorded."""

from __future__ import annotations

import pathlib
import re
import signal
import time

import yaml
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader
from wurde_core import CommsManager, Pose3D, topic
from wurde_core.interfaces import LocalizationPose
from wurde_testing import ChildProcess, find_executable

from rosbag2_schema import check_bagfile_information

STREAM = 'Localization/Dead-Reckoning'
COUNT = 30
DEADLINE = 30.0
DATA, INFO = topic(STREAM, 'data'), topic(STREAM, 'info')
DATA_TYPE = 'wurde_interfaces/msg/LocalizationPoseData'


def _until(predicate, what: str, manager: CommsManager, child: ChildProcess | None = None) -> None:
    deadline = time.monotonic() + DEADLINE
    while not predicate():
        assert child is None or child.process.poll() is None, f'{what}: the child exited: {child.stderr}'
        assert time.monotonic() < deadline, f'{what}: not within {DEADLINE} s'
        manager.step()
        manager.wait(0.05)


def _record(bag: pathlib.Path) -> None:
    """The stream's info (latched) and COUNT poses, recorded into ``bag`` split every 600 bytes."""
    supplier = CommsManager('Recorded')
    supplier.set_no_sleep()
    pose = LocalizationPose(STREAM)
    supplier.register_supplier(pose)
    only = f'^({re.escape(DATA)}|{re.escape(INFO)})$'
    try:
        pose.info.cmd_flags.set_value(7)
        pose.publish_info()
        with ChildProcess([find_executable('wurde_mcp', 'record'), '-o', str(bag), '-t', only,
                           '-b', '600']) as record:
            record.expect('record ready', timeout=60)
            _until(lambda: pose.peers('data') > 0 and f'record: {INFO}: first message' in record.stdout,
                   'the recorder subscribed and has the info', supplier, record)
            for i in range(1, COUNT + 1):
                pose.data.pose = Pose3D(float(i), 0.5, 0.0, 0.1, 0.0, 0.0)
                assert pose.publish_data()
                assert pose.wait_delivered(DEADLINE), f'message {i} not acknowledged by the recorder'
            record.process.send_signal(signal.SIGINT)
            assert record.process.wait(timeout=DEADLINE) == 0, record.stderr
            line = record.expect('messages on', timeout=DEADLINE)
            assert f'{COUNT + 1} messages on 2 topics in {bag}' in line, line
    finally:
        supplier.clean_up()


def _check_metadata(bag: pathlib.Path) -> list[str]:
    """metadata.yaml against rosbag2's schema and the files written; the files' names."""
    document = yaml.safe_load((bag / 'metadata.yaml').read_text())
    assert set(document) == {'rosbag2_bagfile_information'}
    info = document['rosbag2_bagfile_information']
    check_bagfile_information(info)
    names = info['relative_file_paths']
    assert len(names) >= 2 and names == [f'{bag.name}_{k}.mcap' for k in range(len(names))]
    assert sorted(p.name for p in bag.iterdir()) == sorted([*names, 'metadata.yaml'])
    assert [f['path'] for f in info['files']] == names and info['storage_identifier'] == 'mcap'
    assert info['compression_mode'] == info['compression_format'] == ''
    topics = {t['topic_metadata']['name']: t for t in info['topics_with_message_count']}
    assert set(topics) == {DATA, INFO}
    assert topics[DATA]['message_count'] == COUNT and topics[INFO]['message_count'] == 1
    assert info['message_count'] == COUNT + 1 == sum(f['message_count'] for f in info['files'])
    meta = {name: t['topic_metadata'] for name, t in topics.items()}
    assert meta[DATA]['type'] == DATA_TYPE and meta[DATA]['serialization_format'] == 'cdr'
    assert [p['durability'] for p in meta[INFO]['offered_qos_profiles']] == ['transient_local']
    assert [p['durability'] for p in meta[DATA]['offered_qos_profiles']] == ['volatile']
    assert meta[DATA]['type_description_hash'].startswith('RIHS01_')
    first = info['files'][0]['starting_time']['nanoseconds_since_epoch']
    last = max(f['starting_time']['nanoseconds_since_epoch'] + f['duration']['nanoseconds'] for f in info['files'])
    assert info['starting_time']['nanoseconds_since_epoch'] == first and info['duration']['nanoseconds'] == last - first
    for name in names:                       # each file carries the bag's metadata, as rosbag2's storage writes it
        with (bag / name).open('rb') as stream:
            records = [m for m in make_reader(stream).iter_metadata() if m.name == 'rosbag2']
        assert len(records) == 1
        check_bagfile_information(yaml.safe_load(records[0].metadata['serialized_metadata']))
    return names


def test_a_stream_recorded_to_a_split_bag_directory_reads_back_and_replays(ros_domain: int,
                                                                         tmp_path: pathlib.Path) -> None:
    bag = tmp_path / 'run'
    _record(bag)
    _check_metadata(bag)

    # rosbags reads the directory: every pose decoded with the bag's own definitions, and the QoS.
    with AnyReader([bag]) as reader:
        connections = {c.topic: c for c in reader.connections}
        assert [q.durability.name for q in connections[INFO].ext.offered_qos_profiles] == ['TRANSIENT_LOCAL']
        xs = [round(reader.deserialize(raw, DATA_TYPE).pose.x)
              for _, _, raw in reader.messages(connections=[connections[DATA]])]
    assert xs == list(range(1, COUNT + 1))

    # Replayed, a WURDE consumer hears every pose in order, and the info: its info subscription is
    # transient local, so only a replay that offers what the recording kept reaches it.
    listener = CommsManager('Replayed')
    listener.set_no_sleep()
    heard = LocalizationPose(STREAM)
    heard.set_queue_mode(True)
    listener.register_consumer(heard)
    poses: list[int] = []
    flags: list[int] = []

    def take() -> bool:
        while heard.get_next_info():
            flags.append(heard.info.cmd_flags.get_value())
        while heard.get_next_data():
            poses.append(round(heard.data.pose.x()))
        return len(poses) >= COUNT and bool(flags)

    try:
        listener.step()
        with ChildProcess([find_executable('wurde_mcp', 'replay'), str(bag), '-r', '4', '-w', str(DEADLINE)]) as replay:
            _until(take, 'the replayed info and poses', listener, None)
            assert replay.process.wait(timeout=DEADLINE) == 0, replay.stderr
            replay.expect(f'replay: {COUNT + 1} messages', timeout=DEADLINE)
            assert 'replay: 2 topics' in replay.stdout, replay.stdout
        assert poses == list(range(1, COUNT + 1)) and flags == [7]
    finally:
        listener.clean_up()


def test_record_refuses_an_existing_directory_and_splitting_one_file(ros_domain: int, tmp_path: pathlib.Path) -> None:
    existing = tmp_path / 'taken'
    existing.mkdir()
    record = find_executable('wurde_mcp', 'record')
    with ChildProcess([record, '-o', str(existing)]) as child:
        assert child.process.wait(timeout=DEADLINE) == 1
    assert f'record: {existing} exists already' in child.stderr and 'Traceback' not in child.stderr
    assert list(existing.iterdir()) == []
    with ChildProcess([record, '-o', str(tmp_path / 'one.mcap'), '-b', '1000']) as child:
        assert child.process.wait(timeout=DEADLINE) == 2
    assert '-b and -d split a bag directory' in child.stderr and not (tmp_path / 'one.mcap').exists()
