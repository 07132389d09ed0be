"""The ``sim`` camera: the simulated robot's eyes show walls where the map has them — the
renderer against geometry worked out by hand, then a real dummy base and vision_module."""

from __future__ import annotations

import math
import os
import pathlib
from collections.abc import Iterator

import numpy as np
import pytest
from sim_fixture import Observer, sim_config
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.sim.loading import load_sim
from wurde_drivers.sim.render import CEILING, FLOOR, View, render
from wurde_drivers.sim.world import World

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'vision'


def test_a_wall_ahead_fills_the_rows_its_distance_gives() -> None:
    # One wall 2 m ahead, across the view; nothing to the left or right beyond it.
    world = World([(2.0, -1.0, 2.0, 1.0)])
    view = View(width=160, height=120, field_of_view=math.radians(90), camera_height=1.0,
                wall_height=2.0, max_range=10.0)
    image, distance = render(world, 0.0, 0.0, 0.0, view)
    assert image.shape == (120, 160, 3)
    centre = 80             # focal length 80 px: half width / tan(45 deg); a column looking (almost) straight ahead
    assert distance[centre] == pytest.approx(2.0, rel=1e-3)
    # Wall from 1 m above the camera to the floor 1 m below, at 2 m: rows 60 -+ focal * 1 / 2.
    column = image[:, centre]
    wall_rows = np.flatnonzero(np.any(column != CEILING, axis=1) & np.any(column != FLOOR, axis=1))
    assert wall_rows.min() == 60 - 40 and wall_rows.max() == 60 + 40 - 1
    # The wall spans +-1 m at 2 m: +-26.6 degrees, columns 80 -+ 40; outside it, no wall.
    seen = np.isfinite(distance)
    assert seen[41:119].all() and not seen[:39].any() and not seen[121:].any()
    assert np.array_equal(image[:, 10], np.where(np.arange(120)[:, None] + 0.5 >= 60, FLOOR, CEILING))
    # A flat wall is equally tall across a pinhole image (same perpendicular distance), and
    # shaded darker where the ray to it is longer.
    assert np.array_equal(np.any(image[:, 45] != image[:, 10], axis=1), np.any(column != image[:, 10], axis=1))
    assert int(image[60, 45, 0]) < int(image[60, centre, 0])
    # At half the distance the wall is twice as tall: 160 rows, more than the image has.
    near, _ = render(World([(1.0, -1.0, 1.0, 1.0)]), 0.0, 0.0, 0.0, view)
    assert np.count_nonzero(np.any(near[:, centre] != image[:, 10], axis=1)) == 120   # 60 -+ 80: all rows


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({'SimEyesImage': 'ImageTransport', 'PlutoBaseTruth': 'Egomotion'})
    try:
        yield watcher
    finally:
        watcher.close()


def test_sim_camera_sees_the_map_from_the_true_pose(observer: Observer, tmp_path: pathlib.Path) -> None:
    sim = sim_config(tmp_path / 'sim')
    (tmp_path / 'data').mkdir()
    # The camera finds the sim config in the config directory, the writer writes to the data one.
    env = dict(os.environ, WURDE_CONFIG_DIR=str(sim.parent), WURDE_DATA_DIR=str(tmp_path / 'data'))
    args = ['-c', str(CONFIG / 'sim-camera-config.xml'), '-v', str(CONFIG / 'sim-vision-config.xml'),
            '-n', 'SimVision']
    with ChildProcess([find_executable('wurde_drivers', 'dummy_base'), '-c', str(sim), '-n', 'PlutoBase']), \
            ChildProcess([find_executable('wurde_drivers', 'vision_module'), *args], env=env) as vision:
        observer.until(lambda o: bool(o.events['SimEyesImage']) and bool(o.events['PlutoBaseTruth']),
                       'an image of the simulated world and the truth')
        truth = observer.events['PlutoBaseTruth'][-1][1].location
        message = observer.events['SimEyesImage'][-1][1]
        assert vision.stop() == 0
    _, world, start = load_sim(str(sim))
    assert (truth.x, truth.y, truth.theta) == pytest.approx(start)     # the robot stands still
    expected, distance = render(world, *start, View(320, 240, math.radians(60)))
    pixels = np.frombuffer(bytes(message.data), np.uint8).reshape(240, 320, 3)
    assert np.array_equal(pixels, expected[:, :, ::-1])                # rgb of the rendered BGR
    # Walls where the map has them: every column whose ray meets a wall within range shows wall
    # at the horizon; the office's start is in a room, so every column does.
    assert np.isfinite(distance).all()
    horizon = pixels[119]
    for plain in (FLOOR[::-1], CEILING[::-1]):
        assert not np.any(np.all(horizon == plain, axis=1))
    written = sorted((tmp_path / 'data').glob('eyes-*-main-*.ppm'))
    assert written, 'the ImageWriter wrote nothing'



def test_shipped_sim_eyes_run_under_the_mcp(observer: Observer, tmp_path: pathlib.Path) -> None:
    """config/vision/sim-mcp-config.xml as shipped: the MCP starts the dummies and vision_module
    (its -r registration pass included); frames of the office arrive; every module exits 0."""
    root = CONFIG.parents[1]
    env = dict(os.environ, WURDE_CONFIG_DIR=str(root / 'config' / 'sim'), WURDE_DATA_DIR=str(tmp_path),
               WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(CONFIG / 'sim-mcp-config.xml'),
                       '-m', str(CONFIG / 'sim-mcp-mappings.xml'), '-a'], env=env, cwd=tmp_path) as mcp:
        mcp.expect('MCP ready', timeout=60)
        observer.until(lambda o: len(o.events['SimEyesImage']) >= 2, 'sim camera frames under the MCP')
        mcp.stop(timeout=30)
    message = observer.events['SimEyesImage'][-1][1]
    _, world, start = load_sim(str(root / 'config' / 'sim' / 'sim-config.xml'))
    expected, _ = render(world, *start, View(320, 240, math.radians(60)))
    assert bytes(message.data) == expected[:, :, ::-1].tobytes()
    for module in ('PlutoBase', 'PlutoLaser', 'SimVision'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), f'{log[-3000:]}\nMCP: {(mcp.stdout + mcp.stderr)[-3000:]}'
