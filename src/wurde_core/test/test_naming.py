"""wurde_core's names (docs/naming.md): canonical names that collide with nothing users import
beside them, and the guide's names kept as aliases of the very same objects.

No processes, no ROS graph: this only imports modules.
"""

from __future__ import annotations

import importlib
import pathlib
import re

import pytest

import wurde_core
import wurde_core.interfaces
from wurde_core import geometry, logger, timestamp

#: The guide's name -> the canonical name (both exported by ``wurde_core``).
SEED_ALIASES = {'Point': 'PlanarPoint', 'Pose': 'PlanarPose', 'Time': 'Timestamp', 'Logger': 'ModuleLogger'}

#: Where each pair is defined.
DEFINED_IN = {'Point': geometry, 'Pose': geometry, 'Time': timestamp, 'Logger': logger}

#: What a wurde_core user imports beside it: the message packages the suite publishes or reads,
#: rclpy's time and logging, and Python's.
BESIDE = ('geometry_msgs.msg', 'builtin_interfaces.msg', 'sensor_msgs.msg', 'nav_msgs.msg',
          'std_msgs.msg', 'tf2_msgs.msg', 'rcl_interfaces.msg', 'lifecycle_msgs.msg', 'rclpy',
          'rclpy.time', 'rclpy.clock', 'rclpy.duration', 'rclpy.logging', 'logging', 'time',
          'datetime')


@pytest.mark.parametrize('old, new', sorted(SEED_ALIASES.items()))
def test_the_guides_name_is_the_canonical_object(old: str, new: str) -> None:
    assert getattr(wurde_core, old) is getattr(wurde_core, new)
    assert getattr(DEFINED_IN[old], old) is getattr(DEFINED_IN[old], new)
    assert getattr(wurde_core, new).__name__ == new
    assert {old, new} <= set(wurde_core.__all__)


def test_the_logger_is_found_under_both_names_in_interfaces() -> None:
    assert wurde_core.interfaces.Logger is wurde_core.interfaces.ModuleLogger is wurde_core.ModuleLogger


def test_the_wurde_type_names_map_to_the_canonical_views() -> None:
    assert geometry.GEOMETRY['Pose'] is geometry.PlanarPose
    assert geometry.GEOMETRY['Point'] is geometry.PlanarPoint


def test_the_aliases_build_the_same_values() -> None:
    assert wurde_core.Pose(1.0, 2.0, 0.5) == wurde_core.PlanarPose(1.0, 2.0, 0.5)
    assert wurde_core.Time(12.5) == wurde_core.Timestamp(12.5)
    assert repr(wurde_core.Time(1.0)) == 'Timestamp(1.000000)'


@pytest.mark.parametrize('module_name', BESIDE)
def test_no_canonical_export_collides_with_a_name_imported_beside_it(module_name: str) -> None:
    module = importlib.import_module(module_name)
    canonical = set(wurde_core.__all__) - set(SEED_ALIASES)
    assert sorted(name for name in canonical if hasattr(module, name)) == []


def test_every_executable_is_snake_case_or_the_guides_program_name() -> None:
    setup = (pathlib.Path(__file__).resolve().parents[1] / 'setup.py').read_text()
    names = re.findall(r"'([A-Za-z_][A-Za-z0-9_]*) = wurde_core\.", setup)
    assert {'foo_server', 'foo_client'} <= set(names)
    assert sorted(n for n in names if not re.fullmatch('[a-z][a-z0-9_]*', n)) == ['fooServer']
