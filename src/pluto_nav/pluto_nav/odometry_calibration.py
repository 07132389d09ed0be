"""The odometry calibration file (Pluto 6.1: "The calibration data are read from a file and written
to the baseserver when the drive module is started"; 7.1: pose_i sets it from the found wall).

The seed gives no format; ours is two lines of YAML, in the config directory as
``odometry-calibration.yaml`` unless a program is told another path::

    distance-scale: 0.970874    # true distance / distance the raw odometry counts
    rotation-scale: 1.000000    # true angle turned / angle the raw odometry counts

Both keys are required, each once, a number in [0.5, 2]; comments and blank lines are allowed,
anything else is refused with file:line and reason.  The base takes the scales on its command
stream: cmdFlags :data:`CALIBRATE`, force[0..1] = (distance scale, rotation scale) — the protocol
of ``wurde_drivers.streams.calibration``, which this package may not import.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pathlib

from wurde_idl.errors import ConfigError

__all__ = ['CALIBRATE', 'DEFAULT_FILE', 'Calibration', 'read_calibration', 'write_calibration']

#: cmdFlags of the base command that sets the calibration (wurde_drivers.streams.calibration).
CALIBRATE = 99
DEFAULT_FILE = 'odometry-calibration.yaml'
MIN_SCALE, MAX_SCALE = 0.5, 2.0
_KEYS = {'distance-scale': 'distance', 'rotation-scale': 'rotation'}


@dataclasses.dataclass(frozen=True)
class Calibration:
    """Scales of the odometry's distance and rotation increments (1, 1: none)."""

    distance: float = 1.0
    rotation: float = 1.0

    def then(self, distance: float, rotation: float) -> 'Calibration':
        """This calibration corrected by measured factors (true / calibrated odometry)."""
        return Calibration(self.distance * distance, self.rotation * rotation)


def read_calibration(path: str | os.PathLike[str]) -> Calibration:
    """The file's calibration; :class:`ConfigError` (file, line, reason) when it is wrong."""
    name = str(path)
    try:
        text = pathlib.Path(path).read_text()
    except OSError as error:
        raise ConfigError(name, None, f'cannot read the calibration file: {error.strerror}') from None
    values: dict[str, float] = {}
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split('#', 1)[0].strip()
        if not line:
            continue
        key, colon, value = line.partition(':')
        key = key.strip()
        if not colon or key not in _KEYS:
            raise ConfigError(name, number, f'expected "distance-scale: N" or "rotation-scale: N", not {line!r}')
        if _KEYS[key] in values:
            raise ConfigError(name, number, f'{key} given twice')
        try:
            scale = float(value)
        except ValueError:
            raise ConfigError(name, number, f'{key}: {value.strip()!r} is not a number') from None
        if not (math.isfinite(scale) and MIN_SCALE <= scale <= MAX_SCALE):
            raise ConfigError(name, number, f'{key} {scale} is not in [{MIN_SCALE}, {MAX_SCALE}]')
        values[_KEYS[key]] = scale
    missing = [key for key, field in _KEYS.items() if field not in values]
    if missing:
        raise ConfigError(name, None, f'missing {", ".join(missing)}')
    return Calibration(**values)


def write_calibration(path: str | os.PathLike[str], calibration: Calibration) -> None:
    """Write the file (atomically: a driveModule starting meanwhile reads the old or the new one)."""
    for scale in (calibration.distance, calibration.rotation):
        if not (math.isfinite(scale) and MIN_SCALE <= scale <= MAX_SCALE):
            raise ValueError(f'scale {scale} is not in [{MIN_SCALE}, {MAX_SCALE}]: not written')
    target = pathlib.Path(path)
    temporary = target.with_name(target.name + '.tmp')
    temporary.write_text('# Odometry calibration (Pluto 6.1, 7.1), written by pose_i.\n'
                         f'distance-scale: {calibration.distance:.6f}    # true / raw odometry distance\n'
                         f'rotation-scale: {calibration.rotation:.6f}    # true / raw odometry rotation\n')
    os.replace(temporary, target)
