"""``replay`` of rosbag2 bags written by another writer (rosbags), in every layout rosbag2 writes:
played by the real program into a real rclpy subscriber in this process, each message in order,
``/latched`` offered transient local again (a transient-local subscription matches nothing else),
a topic whose type is not installed skipped with a warning naming topic and type; serialization
formats other than CDR and bags that cannot be read refused by name, with a non-zero status and
never a traceback."""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable
from typing import Any

import pytest
import yaml
from mcap.writer import Writer as McapWriter
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String
from wurde_testing import ChildProcess, find_executable

import rosbags_bags
from rosbags_bags import BASIC, CHATTER, LATCHED

DEADLINE = 60.0


def _legacy_mcap(path: pathlib.Path, rows: list[tuple[str, str, int, Any]]) -> pathlib.Path:
    """One MCAP file as ``record`` wrote it before rosbag2's QoS metadata: ``durability`` and
    ``reliability`` channel metadata only."""
    store = rosbags_bags.typestore()
    with path.open('wb') as stream:
        writer = McapWriter(stream)
        writer.start(profile='ros2', library='wurde_mcp record')
        schemas: dict[str, int] = {}
        channels: dict[str, int] = {}
        for topic, type_name, stamp, message in rows:
            if type_name not in schemas:
                schemas[type_name] = writer.register_schema(
                    type_name, 'ros2msg', store.generate_msgdef(type_name, ros_version=2)[0].encode())
            if topic not in channels:
                channels[topic] = writer.register_channel(topic, 'cdr', schemas[type_name], {
                    'durability': 'transient_local' if topic == '/latched' else 'volatile',
                    'reliability': 'reliable'})
            writer.add_message(channels[topic], log_time=stamp, publish_time=stamp,
                               data=bytes(store.serialize_cdr(message, type_name)))
        writer.finish()
    return path


def _mcap_dir(path: pathlib.Path) -> pathlib.Path:
    return rosbags_bags.write(path, rosbags_bags.items())


def _mcap_file_compressed(path: pathlib.Path) -> pathlib.Path:
    bag = rosbags_bags.write(path, rosbags_bags.items(), compression='file')
    assert [p.name for p in bag.iterdir() if p.name != 'metadata.yaml'] == [f'{path.name}.mcap.zstd']
    return bag


def _sqlite_message_compressed(path: pathlib.Path) -> pathlib.Path:
    return rosbags_bags.write(path, rosbags_bags.items(), storage='sqlite3', compression='message')


def _sqlite_split(path: pathlib.Path) -> pathlib.Path:
    bag = rosbags_bags.write_split(path, rosbags_bags.items(), storage='sqlite3')
    assert sorted(p.name for p in bag.iterdir()) == [f'{path.name}_0.db3', f'{path.name}_1.db3', 'metadata.yaml']
    return bag


def _mcap_split_metadata_file(path: pathlib.Path) -> pathlib.Path:
    return rosbags_bags.write_split(path, rosbags_bags.items()) / 'metadata.yaml'


def _mcap_split_metadata_lost(path: pathlib.Path) -> pathlib.Path:
    bag = rosbags_bags.write_split(path, rosbags_bags.items())
    (bag / 'metadata.yaml').unlink()                 # a recorder that died before writing it ...
    cut = (bag / f'{path.name}_1.mcap').read_bytes()
    (bag / f'{path.name}_2.mcap').write_bytes(cut[:len(cut) // 2])     # ... in the middle of a file
    return bag


def _single_mcap(path: pathlib.Path) -> pathlib.Path:
    return rosbags_bags.write(path, rosbags_bags.items()) / f'{path.name}.mcap'


def _single_db3(path: pathlib.Path) -> pathlib.Path:
    return rosbags_bags.write(path, rosbags_bags.items(), storage='sqlite3') / f'{path.name}.db3'


def _old_record_file(path: pathlib.Path) -> pathlib.Path:
    return _legacy_mcap(path.with_suffix('.mcap'), rosbags_bags.items())


BAGS: dict[str, Callable[[pathlib.Path], pathlib.Path]] = {
    'mcap directory': _mcap_dir, 'mcap, zstd file compression': _mcap_file_compressed,
    'sqlite3, zstd message compression': _sqlite_message_compressed, 'sqlite3 split in two': _sqlite_split,
    'mcap split in two, its metadata.yaml': _mcap_split_metadata_file,
    'mcap split in two, metadata.yaml lost': _mcap_split_metadata_lost, 'one .mcap file': _single_mcap,
    'one .db3 file': _single_db3, 'an .mcap of the old record': _old_record_file}


@pytest.mark.parametrize('layout', list(BAGS))
def test_a_bag_replays_into_a_subscriber_with_its_qos(layout: str, rclpy_context: Any,
                                                     tmp_path: pathlib.Path) -> None:
    import rclpy
    bag = BAGS[layout](tmp_path / 'bag')
    node = rclpy.create_node('replay_listener', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    chatter: list[str] = []
    latched: list[str] = []
    node.create_subscription(String, '/chatter', lambda m: chatter.append(m.data),
                             QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE))
    # Transient local: matched only by a transient-local publisher, so it hears only if the
    # recorded offer survived.
    node.create_subscription(String, '/latched', lambda m: latched.append(m.data),
                             QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                        durability=DurabilityPolicy.TRANSIENT_LOCAL))
    try:
        with ChildProcess([find_executable('wurde_mcp', 'replay'), str(bag), '-r', '0',
                           '-w', str(DEADLINE)]) as replay:
            deadline = time.monotonic() + DEADLINE
            while replay.process.poll() is None or len(chatter) < len(CHATTER) or not latched:
                assert time.monotonic() < deadline, (chatter, latched, replay.stdout, replay.stderr)
                executor.spin_once(timeout_sec=0.05)
            assert replay.process.returncode == 0, replay.stderr
        assert chatter == CHATTER and latched == [LATCHED]
        assert 'replay: 2 topics' in replay.stdout and f'replay: {len(CHATTER) + 1} messages' in replay.stdout
        warning = next(line for line in replay.stderr.splitlines() if '/basic' in line)
        assert BASIC in warning and 'not installed' in warning, replay.stderr
        assert 'Traceback' not in replay.stderr
        assert ('no metadata.yaml; its 3 storage files are read one by one' in replay.stderr) == \
            ('bag_2.mcap: not readable as a rosbag2 storage file' in replay.stderr) == layout.endswith('lost'), \
            replay.stderr
    finally:
        executor.shutdown()
        node.destroy_node()


def _refused(bag: pathlib.Path, *args: str) -> ChildProcess:
    """``replay`` run to its end on ``bag``, where it should refuse to play."""
    with ChildProcess([find_executable('wurde_mcp', 'replay'), str(bag), '-w', '0', *args]) as replay:
        replay.process.wait(timeout=DEADLINE)
    assert 'Traceback' not in replay.stderr, replay.stderr
    return replay


@pytest.mark.parametrize('storage', ['mcap', 'sqlite3'])
def test_a_serialization_other_than_cdr_is_refused_by_name(ros_domain: int, storage: str,
                                                           tmp_path: pathlib.Path) -> None:
    bag = rosbags_bags.write(tmp_path / 'bag', rosbags_bags.items(), storage=storage,
                             formats={'/chatter': 'json', '/basic': 'wrong_format'})
    for path in (bag, next(p for p in bag.iterdir() if p.name != 'metadata.yaml')):
        replay = _refused(path)
        assert replay.process.returncode == 1 and 'replay: 0 messages' not in replay.stdout
        assert "serialization format 'json' (/chatter)" in replay.stderr, replay.stderr
        assert "'wrong_format' (/basic)" in replay.stderr and 'only CDR' in replay.stderr
    # Left out with -t, the rest plays.
    replay = _refused(bag, '-t', '^/latched$', '-r', '0')
    assert replay.process.returncode == 0, replay.stderr
    assert 'replay: 1 topics' in replay.stdout and 'replay: 1 messages' in replay.stdout


@pytest.mark.process
def test_a_bag_that_cannot_be_read_is_refused_naming_file_and_reason(tmp_path: pathlib.Path) -> None:
    bag = rosbags_bags.write(tmp_path / 'bag', rosbags_bags.items())
    metadata = yaml.safe_load((bag / 'metadata.yaml').read_text())
    metadata['rosbag2_bagfile_information']['relative_file_paths'].append('bag_1.mcap')
    (bag / 'metadata.yaml').write_text(yaml.safe_dump(metadata))
    garbage = tmp_path / 'garbage.mcap'
    garbage.write_bytes(bytes(range(256)))
    not_yaml = tmp_path / 'notyaml'
    not_yaml.mkdir()
    (not_yaml / 'metadata.yaml').write_text('rosbag2_bagfile_information: [unclosed\n')
    lz4 = rosbags_bags.write(tmp_path / 'lz4', rosbags_bags.items())
    text = (lz4 / 'metadata.yaml').read_text()
    (lz4 / 'metadata.yaml').write_text(text.replace("compression_mode: ''", 'compression_mode: file')
                                       .replace("compression_format: ''", 'compression_format: lz4'))
    cases = {bag: f'{bag / "bag_1.mcap"} is missing', garbage: 'neither an MCAP nor an SQLite',
             not_yaml: f'{not_yaml / "metadata.yaml"}: not YAML', tmp_path / 'absent': 'no such file or directory',
             lz4: "compression format 'lz4' is not supported"}
    for path, reason in cases.items():
        replay = _refused(path)
        assert replay.process.returncode == 1, (path, replay.stdout, replay.stderr)
        assert reason in replay.stderr, (path, replay.stderr)
