"""The odometry calibration file (Pluto 6.1, 7.1; format ours): written and read back, and every
kind of wrong file refused with file:line and reason."""

from __future__ import annotations

import pathlib

import pytest
from wurde_idl.errors import ConfigError

from pluto_nav.odometry_calibration import Calibration, read_calibration, write_calibration


def test_written_file_reads_back(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'odometry-calibration.yaml'
    write_calibration(path, Calibration(0.970874, 1.030928))
    assert read_calibration(path) == Calibration(0.970874, 1.030928)
    assert Calibration(0.99, 1.0).then(0.98, 1.02) == pytest.approx(Calibration(0.9702, 1.02))
    with pytest.raises(ValueError, match='not in'):
        write_calibration(path, Calibration(3.0, 1.0))
    assert read_calibration(path) == Calibration(0.970874, 1.030928)     # the old file stays


@pytest.mark.parametrize('text, where, reason', [
    ('distance-scale: 1\nrotation-scale: 1\nwheelbase: 0.5\n', ':3', 'expected "distance-scale: N"'),
    ('distance-scale: 1\ndistance-scale: 1\n', ':2', 'distance-scale given twice'),
    ('# comment\n\ndistance-scale: one\n', ':3', "distance-scale: 'one' is not a number"),
    ('distance-scale: 1\nrotation-scale: nan\n', ':2', 'rotation-scale nan is not in [0.5, 2.0]'),
    ('distance-scale: 0.2\n', ':1', 'distance-scale 0.2 is not in [0.5, 2.0]'),
    ('distance-scale: 1  # ok\n', '', 'missing rotation-scale'),
    ('distance-scale 1\n', ':1', 'expected'),
])
def test_wrong_files_are_refused_with_file_and_line(tmp_path: pathlib.Path, text: str, where: str, reason: str) -> None:
    path = tmp_path / 'odometry-calibration.yaml'
    path.write_text(text)
    with pytest.raises(ConfigError) as error:
        read_calibration(path)
    assert str(error.value).startswith(f'{path}{where}: '), str(error.value)
    assert reason in str(error.value)


def test_a_missing_file_is_refused(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ConfigError, match='cannot read the calibration file'):
        read_calibration(tmp_path / 'none.yaml')
