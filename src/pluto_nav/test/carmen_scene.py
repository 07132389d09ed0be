"""CARMEN log lines as CARMEN's logger writes them (src/logtools/writelog.c), for the tests."""

from __future__ import annotations

import gzip
import math
import pathlib

DEG = math.pi / 180.0


def tail(stamp: float) -> str:
    return f'{stamp:.6f} testhost {stamp - 1000:.6f}'


def odom(stamp: float, x: float = 0.0, y: float = 0.0, theta: float = 0.0, tv: float = 0.0,
         rv: float = 0.0) -> str:
    return f'ODOM {x:.6f} {y:.6f} {theta:.6f} {tv} {rv} 0.0 {tail(stamp)}'


def flaser(stamp: float, ranges: list[float] | int = 360, robot: tuple[float, float, float] = (0, 0, 0),
           laser: tuple[float, float, float] | None = None, name: str = 'FLASER') -> str:
    values = [1.0 + 0.01 * i for i in range(ranges)] if isinstance(ranges, int) else ranges
    laser = laser or robot
    return (f'{name} {len(values)} ' + ' '.join(f'{r:.2f}' for r in values) + ' '
            + ' '.join(f'{v:.6f}' for v in (*laser, *robot)) + f' {tail(stamp)}')


def robotlaser(stamp: float, ranges: list[float], *, laser: tuple[float, float, float],
               robot: tuple[float, float, float], remissions: list[float] | None = None, number: int = 1,
               start: float = -math.pi / 2, resolution: float = DEG, max_range: float = 50.0,
               with_mode: bool = True) -> str:
    remissions = remissions or []
    fan = f'0 {start:.6f} {resolution * (len(ranges) - 1):.6f} {resolution:.6f} {max_range:.1f} 0.01'
    return (f'ROBOTLASER{number} {fan} {"0 " if with_mode else ""}{len(ranges)} '
            + ' '.join(f'{r:.3f}' for r in ranges) + f' {len(remissions)} '
            + ''.join(f'{m:.1f} ' for m in remissions)
            + ' '.join(f'{v:.6f}' for v in (*laser, *robot)) + f' 0.1 0.0 0.5 0.3 1000000 {tail(stamp)}')


def rawlaser(stamp: float, ranges: list[float], number: int = 1, remissions: list[float] | None = None) -> str:
    remissions = remissions or []
    return (f'RAWLASER{number} 0 -1.570796 3.141593 0.017453 80.0 0.01 0 {len(ranges)} '
            + ' '.join(f'{r:.2f}' for r in ranges) + f' {len(remissions)} '
            + ''.join(f'{m:.1f} ' for m in remissions) + tail(stamp))


def write(path: pathlib.Path, lines: list[str], *, compress: bool = False) -> pathlib.Path:
    text = ('\n'.join(lines) + '\n').encode()
    path.write_bytes(gzip.compress(text) if compress else text)
    return path
