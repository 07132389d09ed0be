"""The ``mount-*`` attributes of every device config, and the covariance arithmetic (no ROS)."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest

from wurde_drivers.dmu.config import load_dmu_config
from wurde_drivers.errors import ConfigError
from wurde_drivers.gps.config import load_gps_config
from wurde_drivers.mounting import Mounting
from wurde_drivers.ptu.config import load_ptu_config
from wurde_drivers.ros_std_covariance import (MIN_VARIANCE, ImuCovariance, ImuNoise, OdometryCovariance,
                                              fix_covariance, lowpass_variance_factor)
from wurde_drivers.sick.config import load_laser_config
from wurde_drivers.sim.config import load_sim_config
from wurde_drivers.wrist.config import load_wrist_config

CONFIG = pathlib.Path(__file__).resolve().parents[3] / 'config'


def test_the_shipped_configs_place_every_device() -> None:
    assert load_dmu_config(CONFIG / 'dmu' / 'dmu-config.xml')[0].mount == Mounting(-0.05, 0.0, 0.3)
    assert load_gps_config(CONFIG / 'gps' / 'gps-config.xml')[0].mount == Mounting(-0.1, 0.05, 0.9)
    assert load_ptu_config(CONFIG / 'ptu' / 'ptu-config.xml')[0].mount == Mounting(0.15, 0.0, 0.7, 0.0)
    assert load_wrist_config(CONFIG / 'wrist' / 'wrist-config.xml')[0].mount == Mounting(0.15, 0.0, 0.7)
    lasers = load_laser_config(CONFIG / 'sick' / 'laser-config.xml')
    assert lasers[0].mount == Mounting(0.2, 0.0, 0.5)
    assert lasers[1].mount == Mounting(0.0, 0.0, 0.4)       # none given: the laser's default height
    sim = load_sim_config(CONFIG / 'pluto' / 'sim-config.xml')
    assert (sim.dmu.mount, sim.gps.mount, sim.wrist.mount) == (
        Mounting(-0.05, 0.0, 0.3), Mounting(-0.1, 0.05, 0.9), Mounting(0.15, 0.0, 0.7))


@pytest.mark.parametrize(('root', 'device', 'reason'), [
    ('dmu-config', '<device port="p" name="d" mount-x="ahead"/>', 'mount-x="ahead" of <device> is not a number'),
    ('dmu-config', '<device port="p" name="d" mount-yaw="1"/>', 'mount-yaw'),   # the DMU reports in robot axes
    ('gps-config', '<device port="p" name="g" mount-z="inf"/>', 'mount-z="inf" of <device> is not finite'),
    ('ptu-config', '<device port="p" name="u" mount-yaw="nan"/>', 'mount-yaw="nan" of <device> is not finite'),
])
def test_a_bad_mounting_is_refused_with_file_and_line(tmp_path: pathlib.Path, root: str, device: str,
                                                       reason: str) -> None:
    path = tmp_path / f'{root}.xml'
    path.write_text(f'<?xml version="1.0"?>\n<{root}>\n  {device}\n</{root}>\n')
    loader = {'dmu-config': load_dmu_config, 'gps-config': load_gps_config, 'ptu-config': load_ptu_config}[root]
    with pytest.raises(ConfigError, match=reason) as caught:
        loader(path)
    assert f'{path}:3' in str(caught.value)


def test_odometry_covariance_grows_with_distance_and_turns_sideways() -> None:
    cov = OdometryCovariance(trans=0.1, rot=0.0, drift=0.0)
    cov.update(0.0, 0.0, 0.0, 0.0)
    cov.update(2.0, 0.0, 0.0, 1.0)                  # 2 m east in 1 s
    pose = np.array(cov.pose6()).reshape(6, 6)
    assert pose[0, 0] == pytest.approx(MIN_VARIANCE + 0.01 * 2.0) and pose[1, 1] == pytest.approx(MIN_VARIANCE)
    assert cov.twist6()[0] == pytest.approx(MIN_VARIANCE + 0.01 * 2.0)        # var(ds) / dt²
    # A heading error (drift: 0.05 rad per m) turns into a sideways error on the next metre.
    cov = OdometryCovariance(trans=0.0, rot=0.0, drift=0.05)
    for i, x in enumerate((0.0, 1.0, 2.0)):
        cov.update(x, 0.0, 0.0, float(i))
    pose = np.array(cov.pose6()).reshape(6, 6)
    assert pose[5, 5] == pytest.approx(MIN_VARIANCE + 2 * 0.05 ** 2)
    assert pose[1, 1] == pytest.approx(MIN_VARIANCE + 0.05 ** 2)               # 1 m at var(theta) 0.05²
    assert pose[2, 2] > 1e5                                                   # z: not measured
    # A turn through ±pi is the short turn, not nearly a whole circle.
    cov = OdometryCovariance(trans=0.0, rot=0.1, drift=0.0)
    cov.update(0.0, 0.0, math.pi - 0.05, 0.0)
    cov.update(0.0, 0.0, -math.pi + 0.05, 1.0)
    assert np.array(cov.pose6()).reshape(6, 6)[5, 5] == pytest.approx(MIN_VARIANCE + 0.1 ** 2 * 0.1)


def test_imu_covariance_from_the_noise_and_the_filter() -> None:
    assert lowpass_variance_factor(0.01, 0.0) == 1.0
    a = 1 - math.exp(-0.5)
    assert lowpass_variance_factor(0.01, 0.02) == pytest.approx(a / (2 - a))
    cov = ImuCovariance(ImuNoise(rate=0.01, accel=0.1, angle=0.02), tau=0.02)
    for i in range(101):
        cov.update(i * 0.01)
    assert cov.angular_velocity()[0] == pytest.approx(MIN_VARIANCE + 1e-4 * a / (2 - a))
    assert cov.linear_acceleration()[4] == pytest.approx(MIN_VARIANCE + 1e-2 * a / (2 - a))
    orientation = cov.orientation()
    assert orientation[0] == pytest.approx(MIN_VARIANCE + 0.02 ** 2)
    assert orientation[8] == pytest.approx(MIN_VARIANCE + 100 * (0.01 * 0.01) ** 2)   # random walk, 1 s


def test_fix_covariance_follows_hdop_and_quality() -> None:
    assert fix_covariance(2, 0.9)[0] == pytest.approx(MIN_VARIANCE + 0.09 ** 2)
    assert fix_covariance(1, 2.0)[8] == pytest.approx(MIN_VARIANCE + 16.0 ** 2)
    assert fix_covariance(6, 1.0)[0] > 1e11            # dead reckoning: no satellite fix
    assert fix_covariance(4, float('nan'))[4] == pytest.approx(MIN_VARIANCE + 0.02 ** 2)
