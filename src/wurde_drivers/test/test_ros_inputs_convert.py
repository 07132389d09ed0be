"""ros_inputs' pure parts: a LaserScan in the suite's order and values, and the laser's mount from
a chain of transforms (no DDS: numpy and scipy only)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from wurde_drivers.ros_inputs.frames import FrameTree, Mount, Transform, mount_of
from wurde_drivers.ros_inputs.scan import suite_ranges, to_robot

LEVEL = Mount(0.0, 0.0, 0.0, 0.0, False, 0.0)
UPSIDE_DOWN = Mount(0.0, 0.0, 0.0, 0.0, True, 0.0)


def transform(xyz: tuple[float, float, float], rpy: tuple[float, float, float]) -> Transform:
    return Transform(Rotation.from_euler('xyz', rpy), np.array(xyz, dtype=float))


def test_special_values_become_the_suites_inf_and_nan() -> None:
    got = suite_ranges([math.nan, math.inf, -math.inf, 30.0, 35.0, 0.01, 0.02, 5.0],
                       range_min=0.02, range_max=30.0)
    want = [math.nan, math.inf, math.nan, math.inf, math.inf, math.nan, 0.02, 5.0]
    np.testing.assert_array_equal(got, want)
    assert not np.any(got < 0)        # -1 is the SICK's fatal error: never in a normal scan
    # a driver that names no range_max: only inf saw nothing; no range_min: only negatives
    np.testing.assert_array_equal(suite_ranges([0.0, 50.0, math.inf, -0.5], range_min=math.nan,
                                               range_max=0.0), [0.0, 50.0, math.inf, math.nan])


@pytest.mark.parametrize('increment_sign, mount, reversed_', [
    (+1, LEVEL, False), (-1, LEVEL, True), (+1, UPSIDE_DOWN, True), (-1, UPSIDE_DOWN, False)])
def test_the_beams_come_counter_clockwise_for_the_robot(increment_sign: int, mount: Mount,
                                                        reversed_: bool) -> None:
    count, fov = 1081, math.radians(270)
    step = fov / (count - 1)
    ranges = 1.0 + 0.001 * np.arange(count)
    start = -fov / 2 if increment_sign > 0 else fov / 2
    scan = to_robot(ranges, angle_min=start, angle_increment=increment_sign * step, range_min=0.0,
                    range_max=30.0, stamp=100.0, time_increment=1e-4, mount=mount)
    assert scan.step == pytest.approx(step) and scan.first == pytest.approx(-fov / 2)
    np.testing.assert_allclose(scan.ranges, ranges[::-1] if reversed_ else ranges)
    # each beam's robot bearing is where the laser pointed it
    for index in (0, 100, 1080):
        laser_angle = start + increment_sign * step * index
        robot_index = count - 1 - index if reversed_ else index
        assert scan.first + scan.step * robot_index == pytest.approx(mount.bearing(laser_angle))
    assert scan.centre == pytest.approx(100.0 + 540 * 1e-4) and scan.end == pytest.approx(100.108)


def test_a_turned_laser_puts_its_fan_at_its_yaw() -> None:
    mount = Mount(0.1, 0.0, 0.3, math.pi, True, 0.0)     # backwards and upside down
    scan = to_robot([1.0, 2.0, 3.0], angle_min=-0.1, angle_increment=0.1, range_min=0.0,
                    range_max=10.0, stamp=5.0, time_increment=0.0, mount=mount)
    # laser angle +0.1 is robot bearing pi - 0.1; robot order starts there
    assert scan.first == pytest.approx(math.pi - 0.1)
    np.testing.assert_allclose(scan.ranges, [3.0, 2.0, 1.0])
    assert scan.centre == scan.end == 5.0       # no time increment: the header's stamp


@pytest.mark.parametrize('ranges, angle_min, increment, reason', [
    ([1.0], 0.0, 0.1, '1 beams'), ([1.0, 2.0], 0.0, 0.0, 'no direction'),
    ([1.0, 2.0], math.nan, 0.1, 'no direction')])
def test_scans_without_a_fan_are_refused(ranges: list[float], angle_min: float, increment: float,
                                         reason: str) -> None:
    with pytest.raises(ValueError, match=reason):
        to_robot(ranges, angle_min=angle_min, angle_increment=increment, range_min=0.0,
                 range_max=10.0, stamp=0.0, time_increment=0.0, mount=LEVEL)


def test_the_mount_is_composed_through_the_chain_and_found_upside_down() -> None:
    tree = FrameTree()
    tree.set('odom', 'base_link', transform((5.0, 1.0, 0.0), (0.0, 0.0, 1.0)))   # moving: irrelevant
    tree.set('base_link', 'mount', transform((0.2, 0.0, 0.3), (0.0, 0.0, math.pi / 2)))
    tree.set('mount', 'laser', transform((0.1, 0.0, 0.05), (math.pi, 0.0, 0.0)))
    mount = mount_of(tree.lookup('base_link', 'laser'))
    assert (mount.x, mount.y, mount.z) == pytest.approx((0.2, 0.1, 0.35))
    assert mount.yaw == pytest.approx(math.pi / 2) and mount.upside_down and mount.tilt == pytest.approx(0.0)
    # the laser's +x beam points along the robot's +y; its +90 deg beam (laser y) along robot -x
    assert mount.bearing(0.0) == pytest.approx(math.pi / 2)
    assert math.remainder(mount.bearing(math.pi / 2), math.tau) == pytest.approx(0.0, abs=1e-9)
    # a base frame below a common ancestor: base_footprint and laser both hang off base_link
    tree.set('base_link', 'base_footprint', transform((0.0, 0.0, -0.1), (0.0, 0.0, 0.0)))
    inner = mount_of(tree.lookup('base_footprint', 'laser'))
    assert (inner.x, inner.y, inner.z) == pytest.approx((0.2, 0.1, 0.45))
    assert tree.lookup('base_link', 'nowhere') is None
    assert tree.lookup('base_link', 'base_link') is not None


def test_a_newer_edge_replaces_the_old_one_and_a_cycle_ends() -> None:
    tree = FrameTree()
    tree.set('base_link', 'laser', transform((0.1, 0.0, 0.0), (0.0, 0.0, 0.0)))
    tree.set('base_link', 'laser', transform((0.3, 0.0, 0.0), (0.0, 0.0, 0.0)))
    assert mount_of(tree.lookup('base_link', 'laser')).x == pytest.approx(0.3)
    tree.set('a', 'b', Transform.identity())
    tree.set('b', 'a', Transform.identity())
    assert tree.lookup('base_link', 'a') is None
    with pytest.raises(ValueError):
        Transform.from_values((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError):
        Transform.from_values((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))


def test_a_tilted_laser_says_so() -> None:
    mount = mount_of(transform((0.0, 0.0, 0.0), (0.0, math.radians(10), 0.0)))
    assert mount.tilt == pytest.approx(math.radians(10)) and not mount.upside_down
    assert mount.close_to(Mount(0.0, 0.0, 0.0, 0.0, False, 0.0))
    assert not mount.close_to(Mount(0.0, 0.0, 0.0, 0.0, True, 0.0))
    assert not mount.close_to(Mount(0.01, 0.0, 0.0, 0.0, False, 0.0))
