"""The installed TFMessage is upstream Jazzy's: same definition, same RIHS01 type hash.

Whatever tf2_msgs the environment provides is checked (the stand-in after `make build`, the
real one with ROS 2 from apt), against the values recorded in :mod:`upstream`.
"""

from __future__ import annotations

import json
import pathlib
from typing import Any

import pytest
from ament_index_python.packages import get_package_share_directory
from rosidl_generator_type_description import calculate_type_hash

import upstream

SOURCE = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope='module')
def share() -> pathlib.Path:
    return pathlib.Path(get_package_share_directory('tf2_msgs'))


@pytest.fixture(scope='module')
def description(share: pathlib.Path) -> dict[str, Any]:
    """The installed type description of TFMessage (written by rosidl at build time)."""
    return json.loads((share / 'msg' / 'TFMessage.json').read_text())


def test_source_definition_is_upstreams_byte_for_byte() -> None:
    assert (SOURCE / 'msg' / 'TFMessage.msg').read_bytes() == upstream.DEFINITION


def test_installed_definition_is_upstreams(share: pathlib.Path) -> None:
    assert (share / 'msg' / 'TFMessage.msg').read_bytes() == upstream.DEFINITION


def test_type_hash_is_upstreams(description: dict[str, Any]) -> None:
    hashes = {h['type_name']: h['hash_string'] for h in description['type_hashes']}
    assert hashes[upstream.TYPE_NAME] == upstream.TYPE_HASH


def test_referenced_types_hash_as_upstreams(description: dict[str, Any]) -> None:
    hashes = {h['type_name']: h['hash_string'] for h in description['type_hashes']}
    del hashes[upstream.TYPE_NAME]
    assert hashes == upstream.REFERENCED_HASHES


def test_hash_recomputed_by_rosidl_from_the_description(description: dict[str, Any]) -> None:
    """rosidl's own hash function over the installed description, not just the stored string."""
    assert calculate_type_hash(description['type_description_msg']) == upstream.TYPE_HASH


def test_a_changed_definition_would_change_the_hash(description: dict[str, Any]) -> None:
    """The check above can fail: renaming the one field gives another hash."""
    changed = json.loads(json.dumps(description['type_description_msg']))
    changed['type_description']['fields'][0]['name'] = 'transform'
    assert calculate_type_hash(changed) != upstream.TYPE_HASH
