"""sim-config.xml: what the simulated robot is, read by every dummy module (Pluto 5's dummies).

One file describes the whole dummy robot, so the dummies agree on the world, the seed and the
time scale: the map and start place, the base, its odometry noise (zero by default, as the seed's
ideal dummy), the sonar ring, lasers, wrist, DMU, GPS, and the people walking about
(``<person>``, :mod:`.person_config`; where one is at a stamp, :mod:`.walk`).  Every element but
``map`` and ``base`` is optional and every attribute has a default; docs/wurde-drivers.md
("sim.config") shows the whole file with them, and must be kept in step with the defaults here.

The ``mount-*`` attributes place a device on the robot (:mod:`wurde_drivers.mounting`); the sonar
ring and the bumpers are placed by ``<sonar>`` and the base's ``radius``.  The ground truth of
the base is the stream ``<base name>Truth``; the other dummies read it.

Wrong files are refused with file, line and reason; a ``<person>`` with its own line, and, once
the map is read (:mod:`.crowd`), when its path would touch a wall or the robot at its start.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pathlib
from collections.abc import Iterable

from wurde_idl.errors import ConfigError

from ..mounting import MOUNT_ATTRIBUTES, MOUNT_XYZ, Mounting, read_mounting
from ..rflex.robots import BODY_M, ROBOTS, DriveKind
from ..sick import facts as sick_facts
from ..xml_config import Attributes, children, local_name, read_root
from .body import BumperRing, SonarRing
from .kinematics import DriveLimits
from .laser import LaserGeometry
from .person_config import PERSON_ATTRIBUTES, PersonConfig, read_person
from .robot import OdometryNoise, RobotSpec

__all__ = ['BaseConfig', 'DmuConfig', 'GpsConfig', 'PersonConfig', 'SimConfig', 'WristConfig',
           'load_sim_config']


#: The bumper disc's radius (m) per base type when ``radius`` is not given: 0.35 as before for the
#: ATRV-Jr and the B21r (B21ir), the disc round the body (:data:`BODY_M`) for Pluto's ATRV2.
DEFAULT_RADIUS_M = {'ATRVJr': 0.35, 'B21r': 0.35, 'B21ir': 0.35,
                    'ATRV2': round(math.hypot(*BODY_M['ATRV2'][:2]) / 2, 2)}


@dataclasses.dataclass(frozen=True)
class BaseConfig:
    name: str = 'PlutoBase'
    #: rflex-config's robot types (:data:`wurde_drivers.rflex.robots.ROBOTS`): ATRVJr and ATRV2 (skid
    #: steer) supply a RobotDrive, B21r and B21ir (synchro drive) a SynchroDrive, as the real bases.
    type: str = 'ATRVJr'
    rate: float = 10.0            # Hz of simulated time: odometry, bumpers, power
    command_timeout: float = 1.0  # s: the base stops when commands stop coming
    sonar_rate: float = 10.0

    @property
    def truth_stream(self) -> str:
        return f'{self.name}Truth'

    @property
    def synchro(self) -> bool:
        """Whether the base is a synchro drive (SynchroDrive stream) rather than skid steered."""
        return ROBOTS[self.type].drive is DriveKind.SYNCHRO


@dataclasses.dataclass(frozen=True)
class WristConfig:
    name: str = 'PlutoWrist'
    rate: float = 20.0
    max_velocity: float = 1.0
    max_acceleration: float = 2.0
    pan_min: float = -2.9
    pan_max: float = 2.9
    tilt_min: float = -0.8
    tilt_max: float = 0.5
    mount: Mounting = Mounting()


@dataclasses.dataclass(frozen=True)
class DmuConfig:
    name: str = 'PlutoDMU'
    rate: float = 50.0
    rate_bias: float = 0.0
    rate_noise: float = 0.0
    cutoff: float = 5.0
    mount: Mounting = Mounting()


@dataclasses.dataclass(frozen=True)
class GpsConfig:
    name: str = 'PlutoGPS'
    rate: float = 1.0
    latitude: float = 59.3498
    longitude: float = 18.0707
    altitude: float = 30.0
    noise: float = 0.0
    satellites: int = 8
    quality: int = 2
    hdop: float = 0.9
    mount: Mounting = Mounting()


@dataclasses.dataclass(frozen=True)
class SimConfig:
    path: str
    map_file: str
    start: str | tuple[float, float, float]
    seed: int = 1
    time_scale: float = 1.0
    step: float = 0.02
    base: BaseConfig = BaseConfig()
    robot: RobotSpec = RobotSpec()
    lasers: dict[str, LaserGeometry] = dataclasses.field(default_factory=dict)
    wrist: WristConfig | None = None
    dmu: DmuConfig | None = None
    gps: GpsConfig | None = None
    people: tuple[PersonConfig, ...] = ()


_ELEMENTS = ('map', 'base', 'odometry-noise', 'sonar', 'laser', 'wrist', 'dmu', 'gps', 'person')


def _start(attrs: Attributes) -> str | tuple[float, float, float]:
    text = attrs.text('start', 'start')
    parts = text.replace(',', ' ').split()
    if len(parts) == 3:
        try:
            x, y, theta = (float(p) for p in parts)
        except ValueError:
            return text
        if not all(math.isfinite(v) for v in (x, y, theta)):
            raise attrs.error(f'start="{text}" is not finite')
        return x, y, theta
    return text


def load_sim_config(path: str | os.PathLike[str]) -> SimConfig:
    """Read and check a sim-config file.

    :param path: the sim-config.xml; the map's path in it is relative to this file.
    :raises ConfigError: with file, line and reason.
    """
    path = os.fspath(path)
    root = read_root(path, 'sim-config')
    top = Attributes(path, root, optional=('seed', 'time-scale', 'step'))
    seed = top.number('seed', 1, integer=True, minimum=0)
    time_scale = top.number('time-scale', 1.0, minimum=0.01, maximum=1000.0)
    step = top.number('step', 0.02, minimum=0.001, maximum=0.5)
    found: dict[str, Attributes] = {}
    lasers: dict[str, LaserGeometry] = {}
    people: dict[str, PersonConfig] = {}
    for node in children(path, root, _ELEMENTS):
        a = Attributes(path, node, **_SCHEMA[local_name(node)])
        if a.tag == 'person':
            person = read_person(a)
            if person.name in people:
                raise a.error(f'person "{person.name}" is defined twice (first at line '
                              f'{people[person.name].line})')
            people[person.name] = person
            continue
        if a.tag == 'laser':
            name = a.text('name')
            if name in lasers:
                raise a.error(f'laser "{name}" is defined twice')
            lasers[name] = _laser(a)
            continue
        if a.tag in found:
            raise a.error(f'<{a.tag}> appears twice (first at line {found[a.tag].line})')
        found[a.tag] = a
    for needed in ('map', 'base'):
        if needed not in found:
            raise ConfigError(path, root.sourceline, f'<sim-config> needs a <{needed}> element')
    m = found['map']
    map_file = str((pathlib.Path(path).parent / m.text('file')).resolve())
    base, limits, bumpers = _base(found['base'])
    sonar = _sonar(found.get('sonar'))
    noise = _noise(found.get('odometry-noise'))
    spec = RobotSpec(limits=limits, sonar=sonar, bumpers=bumpers, odometry_noise=noise)
    if 'sonar' in found:
        base = dataclasses.replace(base, sonar_rate=found['sonar'].number('rate', 10.0, minimum=0.1))
    _check_visible(path, people.values(), lasers, sonar)
    return SimConfig(path=path, map_file=map_file, start=_start(m), seed=seed,
                     time_scale=time_scale, step=step, base=base, robot=spec, lasers=lasers,
                     wrist=_wrist(found.get('wrist')), dmu=_dmu(found.get('dmu')),
                     gps=_gps(found.get('gps')), people=tuple(people.values()))


def _check_visible(path: str, people: Iterable[PersonConfig], lasers: dict[str, LaserGeometry],
                   sonar: SonarRing) -> None:
    """Refuse a person the sensors could not see: a laser's or the sonars' beams pass above a
    body no taller than their height, and a ghost that bumps the robot unseen is no test."""
    sensors = [(f'laser "{name}"', laser.mount_z) for name, laser in lasers.items()]
    sensors.append(('the sonars', sonar.mount_z))
    for person in people:
        for sensor, height in sensors:
            if person.body.height <= height:
                raise ConfigError(path, person.line,
                                  f'person "{person.name}" is {person.body.height:g} m tall and '
                                  f'{sensor} is {height:g} m above the floor: it could not see the '
                                  'person; make the person taller than every sensor')


_SCHEMA: dict[str, dict[str, tuple[str, ...]]] = {
    'map': {'required': ('file',), 'optional': ('start',)},
    'base': {'optional': ('name', 'type', 'rate', 'command-timeout', 'max-tv', 'max-rv', 'tv-accel',
                          'rv-accel', 'radius')},
    'odometry-noise': {'optional': ('trans', 'rot', 'drift', 'scale', 'turn-scale')},
    'sonar': {'optional': ('count', 'radius', 'max-range', 'half-angle', 'rate')},
    'laser': {'required': ('name',), 'optional': ('model', 'count', 'units', 'inverted', 'baud',
                                                   *MOUNT_XYZ, 'noise')},
    'wrist': {'optional': ('name', 'rate', 'max-velocity', 'max-acceleration', 'pan-min', 'pan-max',
                           'tilt-min', 'tilt-max', *MOUNT_ATTRIBUTES)},
    'dmu': {'optional': ('name', 'rate', 'rate-bias', 'rate-noise', 'cutoff', *MOUNT_XYZ)},
    'gps': {'optional': ('name', 'rate', 'latitude', 'longitude', 'altitude', 'noise', 'satellites',
                         'quality', 'hdop', *MOUNT_XYZ)},
    'person': {'required': ('name',), 'optional': PERSON_ATTRIBUTES[1:]},
}


def _base(a: Attributes) -> tuple[BaseConfig, DriveLimits, BumperRing]:
    base = BaseConfig(name=a.text('name', 'PlutoBase'), type=a.choice('type', tuple(DEFAULT_RADIUS_M), 'ATRVJr'),
                      rate=a.number('rate', 10.0, minimum=0.1, maximum=1000.0),
                      command_timeout=a.number('command-timeout', 1.0, minimum=0.05))
    limits = DriveLimits(max_tv=a.number('max-tv', 1.0, minimum=0.0),
                         max_rv=a.number('max-rv', 1.5, minimum=0.0),
                         tv_accel=a.number('tv-accel', 1.0, minimum=0.0),
                         rv_accel=a.number('rv-accel', 2.0, minimum=0.0))
    radius = a.number('radius', DEFAULT_RADIUS_M[base.type], minimum=0.05, maximum=5.0)
    return base, limits, BumperRing(radius=radius)


def _sonar(a: Attributes | None) -> SonarRing:
    if a is None:
        return SonarRing()
    return SonarRing(count=a.number('count', 16, integer=True, minimum=1, maximum=64),
                     radius=a.number('radius', 0.3, minimum=0.0),
                     max_range=a.number('max-range', 8.0, minimum=0.1),
                     half_angle=a.number('half-angle', math.radians(12.5), minimum=0.0, maximum=math.pi / 2))


def _noise(a: Attributes | None) -> OdometryNoise:
    if a is None:
        return OdometryNoise()
    return OdometryNoise(trans=a.number('trans', 0.0, minimum=0.0), rot=a.number('rot', 0.0, minimum=0.0),
                         drift=a.number('drift', 0.0),
                         scale=a.number('scale', 1.0, minimum=0.5, maximum=2.0),
                         turn_scale=a.number('turn-scale', 1.0, minimum=0.5, maximum=2.0))


def _laser(a: Attributes) -> LaserGeometry:
    model = a.choice('model', sick_facts.KINDS, 'LMS')
    count = int(a.choice('count', tuple(str(n) for n in sick_facts.VALUES_AT.values()), '361'))
    units = a.choice('units', sick_facts.UNITS, 'cm')
    problem = sick_facts.variant_error(model, count, units)
    if problem is not None:
        raise a.error(problem)
    return LaserGeometry(model=model, count=count, units=units,
                         inverted=a.boolean('inverted', False),
                         baudrate=int(a.choice('baud', ('9600', '19200', '38400', '500000'), '38400')),
                         mount_x=a.number('mount-x', 0.0), mount_y=a.number('mount-y', 0.0),
                         mount_z=a.number('mount-z', 0.4), noise_sigma=a.number('noise', 0.0, minimum=0.0))


def _wrist(a: Attributes | None) -> WristConfig | None:
    if a is None:
        return None
    return WristConfig(name=a.text('name', 'PlutoWrist'), rate=a.number('rate', 20.0, minimum=0.1),
                       max_velocity=a.number('max-velocity', 1.0, minimum=0.0),
                       max_acceleration=a.number('max-acceleration', 2.0, minimum=0.0),
                       pan_min=a.number('pan-min', -2.9), pan_max=a.number('pan-max', 2.9),
                       tilt_min=a.number('tilt-min', -0.8), tilt_max=a.number('tilt-max', 0.5),
                       mount=read_mounting(a))


def _dmu(a: Attributes | None) -> DmuConfig | None:
    if a is None:
        return None
    return DmuConfig(name=a.text('name', 'PlutoDMU'), rate=a.number('rate', 50.0, minimum=0.1),
                     rate_bias=a.number('rate-bias', 0.0), rate_noise=a.number('rate-noise', 0.0, minimum=0.0),
                     cutoff=a.number('cutoff', 5.0, minimum=0.01), mount=read_mounting(a))


def _gps(a: Attributes | None) -> GpsConfig | None:
    if a is None:
        return None
    return GpsConfig(name=a.text('name', 'PlutoGPS'), rate=a.number('rate', 1.0, minimum=0.01),
                     latitude=a.number('latitude', 59.3498, minimum=-90.0, maximum=90.0),
                     longitude=a.number('longitude', 18.0707, minimum=-180.0, maximum=180.0),
                     altitude=a.number('altitude', 30.0), noise=a.number('noise', 0.0, minimum=0.0),
                     satellites=a.number('satellites', 8, integer=True, minimum=0, maximum=32),
                     quality=a.number('quality', 2, integer=True, minimum=0, maximum=8),
                     hdop=a.number('hdop', 0.9, minimum=0.0), mount=read_mounting(a))
