"""The manual's examples (docs/movement.md) of the other modules' proxies and of the calibration file: the WristProxy
example turns the dummy wrist as written; the calibration file example is a file the reader takes."""

from __future__ import annotations

import os
import pathlib
import re

import pytest
from drive_fixture import program, room_config
from wurde_testing import ChildProcess

from pluto_nav.odometry_calibration import read_calibration
from wurde_testing.manual import example

def test_wrist_proxy_example_turns_the_wrist(ros_domain: int, tmp_path: pathlib.Path) -> None:
    script = tmp_path / 'look_left.py'
    script.write_text(example('wrist_proxy', 'python'))
    directory = room_config(tmp_path)
    with program('wurde_drivers', 'dummy_base', directory, '-n', 'PlutoBase'), \
            program('wurde_drivers', 'dummy_wrist', directory, '-n', 'PlutoWrist'), \
            ChildProcess([str(script)], env=dict(os.environ)) as client:
        line = client.expect('pan', timeout=90)
        assert client.process.wait(timeout=30) == 0
    found = re.fullmatch(r'pan (\S+)', line)
    # The example stops waiting within 0.01 rad of 0.5 and prints two decimals: 0.49 to 0.51
    # (a fresh-clone make test printed 0.49, which float arithmetic put just past 0.01).
    assert found and float(found.group(1)) == pytest.approx(0.5, abs=0.015), line


def test_calibration_file_example_is_read(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'odometry-calibration.yaml'
    path.write_text(example('calibration_file', 'yaml'))
    found = read_calibration(path)
    assert (found.distance, found.rotation) == pytest.approx((0.971178, 1.028928))
