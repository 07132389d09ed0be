"""CARMEN's localize and map calls (pluto_motion.carmen) against the real localModule and map
server: a gaussian initialization puts the robot at the mean with the deviations given, the
globalpos message and query carry it (not converged: a user's pose), the uniform one and the
particle query are refused; carmen_navigator_get_map gives the map server's grid in CARMEN's
x-major order, and no map of the kinds our navigator does not keep."""

from __future__ import annotations

import contextlib
import pathlib

import pytest
from lxml import etree
from carmen_fixture import carmen_and_robot, odometry_supplier, send_odometry, until
from motion_fixture import program
from wurde_core.interfaces import MapServer

from pluto_motion.carmen import (CARMEN_NAVIGATOR_COST_v, CARMEN_NAVIGATOR_MAP_v, CARMEN_SUBSCRIBE_LATEST,
                                 carmen_localize_initialize_gaussian_command,
                                 carmen_localize_initialize_uniform_command, carmen_localize_query_globalpos,
                                 carmen_localize_query_particles, carmen_localize_subscribe_globalpos_message,
                                 carmen_navigator_get_map, carmen_point_t)

ROOT = pathlib.Path(__file__).resolve().parents[3]
OFFICE = ROOT / 'config' / 'maps' / 'office.xml'


def test_a_gaussian_initialization_sets_the_pose_and_its_deviations(ros_domain: int, tmp_path: pathlib.Path,
                                                                       capfd: pytest.CaptureFixture[str]) -> None:
    (tmp_path / 'map.xml').write_bytes(OFFICE.read_bytes())
    with program('pluto_nav', 'local_module', tmp_path, '-n', 'localModule', '-m', 'map.xml') as local, \
            carmen_and_robot() as (ipc, robot):
        ego = odometry_supplier(robot)
        stamp = [100.0]

        def tick() -> None:                     # the base standing still at 10 Hz of its clock
            if ego.peers():
                stamp[0] += 0.1
                send_odometry(ego, stamp[0], x=0.0)
        globalpos = carmen_localize_subscribe_globalpos_message(None, None, CARMEN_SUBSCRIBE_LATEST)
        until(lambda: globalpos.timestamp > 0, 'the localization heard', timeout=120, every=tick)
        assert (globalpos.globalpos.x, globalpos.globalpos.y) == (3.0, 7.5)     # the map's start
        mean, std = carmen_point_t(5.0, 6.0, 0.5), carmen_point_t(0.2, 0.3, 0.1)
        assert carmen_localize_initialize_gaussian_command(mean, std) == 0
        until(lambda: abs(globalpos.globalpos.x - 5.0) < 1e-6, 'the pose set', timeout=60, every=tick)
        g = globalpos
        assert (g.globalpos.y, g.globalpos.theta) == (pytest.approx(6.0), pytest.approx(0.5))
        assert g.globalpos_std.x == pytest.approx(0.2, abs=0.02)
        assert g.globalpos_std.y == pytest.approx(0.3, abs=0.02)
        assert g.globalpos_std.theta == pytest.approx(0.1, abs=0.02)
        assert g.converged == 0 and g.host == 'localModule'
        assert (g.odometrypos.x, g.odometrypos.y) == (0.0, 0.0)                 # the base's own frame
        queried = carmen_localize_query_globalpos()
        assert queried is not None and queried is not globalpos
        assert queried.globalpos.x == pytest.approx(5.0)
        assert carmen_localize_initialize_uniform_command() == -1
        assert carmen_localize_query_particles() is None
        err = capfd.readouterr().err
        assert 'localize does not support a uniform initialization' in err
        assert 'localize keeps no particles' in err
        assert local.process.poll() is None


def test_an_initialization_while_the_pose_module_holds_the_pose_follows_pluto_7_1(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The poseModule is stopped, the pose written (not converged, at the mean), the poseModule
    started again (converged): Pluto 7.1's procedure, driven by the program's loop."""
    (tmp_path / 'map.xml').write_bytes(OFFICE.read_bytes())
    tree = etree.parse(str(ROOT / 'config' / 'pluto' / 'sim-config.xml'))
    tree.write(str(tmp_path / 'sim-config.xml'))
    specs = [('wurde_drivers', 'dummy_base', ('-n', 'PlutoBase')),
             ('wurde_drivers', 'dummy_sick', ('-n', 'PlutoLaser')),
             ('pluto_nav', 'local_module', ('-n', 'localModule', '-m', 'map.xml')),
             ('pluto_nav', 'pose_module', ('-n', 'poseModule', '-m', 'map.xml'))]
    with contextlib.ExitStack() as stack:
        children = [stack.enter_context(program(package, name, tmp_path, *args)) for package, name, args in specs]
        ipc, _ = stack.enter_context(carmen_and_robot())
        seen: list[tuple[float, float, int]] = []
        carmen_localize_subscribe_globalpos_message(
            None, lambda g: seen.append((g.globalpos.x, g.globalpos.y, g.converged)), CARMEN_SUBSCRIBE_LATEST)
        until(lambda: seen and seen[-1][2] == 1, 'the poseModule holds the pose', timeout=180)
        mark = len(seen)
        assert carmen_localize_initialize_gaussian_command(carmen_point_t(3.3, 7.6, 0.1),
                                                          carmen_point_t(0.2, 0.2, 0.05)) == 0

        def at_mean() -> int | None:
            return next((i for i, (x, y, c) in enumerate(seen[mark:], mark)
                         if c == 0 and abs(x - 3.3) < 0.05 and abs(y - 7.6) < 0.05), None)
        until(lambda: at_mean() is not None, 'the pose set, not converged', timeout=60)
        until(lambda: seen[-1][2] == 1, 'the poseModule started again', timeout=60)
        assert all(child.process.poll() is None for child in children)


def test_the_navigator_map_is_the_map_servers_grid_in_carmens_order(ros_domain: int,
                                                                    tmp_path: pathlib.Path) -> None:
    (tmp_path / 'map.xml').write_bytes(OFFICE.read_bytes())
    with program('wurde_mcp', 'map_server', tmp_path, '-n', 'map_server', '-m', 'map.xml'), \
            carmen_and_robot() as (ipc, robot):
        grid = MapServer('MapServer')
        ipc.manager.register_consumer(grid)
        until(lambda: grid.get_next_info() or grid.info.width.get_value() > 0, 'the map server', timeout=120)
        m = carmen_navigator_get_map(CARMEN_NAVIGATOR_MAP_v)
        assert m is not None and carmen_navigator_get_map(CARMEN_NAVIGATOR_MAP_v) is not m
        width, height = grid.info.width.get_value(), grid.info.height.get_value()
        cells = list(grid.info.cells.get_value())
        assert (m.config.x_size, m.config.y_size, m.size) == (width, height, width * height)
        assert m.config.resolution == pytest.approx(grid.info.resolution.get_value())
        assert m.map_type == CARMEN_NAVIGATOR_MAP_v and m.host == 'map_server'
        for x, y in ((0, 0), (width - 1, 0), (3, height - 2), (width // 2, height // 3)):
            assert m.data[x * height + y] == cells[y * width + x]
        assert 0 < sum(1 for v in m.data if v == 1.0) < m.size        # walls and free space
        assert carmen_navigator_get_map(CARMEN_NAVIGATOR_COST_v) is None
        with pytest.raises(ValueError, match='carmen_navigator_map_t'):
            carmen_navigator_get_map(42)
