"""The robots an rFLEX controller drives (B21r, ATRV-Jr, and Pluto's ATRV2): units, sonars, bumpers,
conversions.

Pure data and arithmetic; no I/O. WURDE 7.6 names the B21r and the ATRV-Jr; the guide's appendix
rflex-config (10.1.5) writes ``type="B21ir"``, which is the B21r here under the name the appendix
prints; ``ATRV2`` is Pluto's own robot (Pluto 2: "ATRV2 (baseserver)").  No public source gives
the ATRV2's rFLEX encoder factors or sonar positions: it takes the ATRV-Jr's and differs in its
body (:data:`BODY_M`).

Units per metre / radian (docs/protocols.md 3 lists two rows per robot): the B21r's
103000 / 35000 and the ATRV-Jr's 90810 / 37000 are Player's and DLu's rows; CARMEN's are one
site's calibration, and Pluto's driveModule calibrates odometry at run time anyway (Pluto doc 2).
:func:`dataclasses.replace` gives a robot with other factors.

Sonar ids are ``bank * 16 + index``; bumpers (B21r only) are DIO panels 0x40-0x4D; voltage is
``raw / 100 + 1.2`` V, a raw 0 meaning "not measured".  docs/wurde-drivers.md ("rflex.robots")
gives the sonar rings and the panels.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import math

__all__ = ['ATRV2', 'ATRV_JR', 'B21IR', 'B21R', 'BODY_M', 'BumperPanel', 'DriveKind', 'ROBOTS', 'RobotParams',
           'SONAR_NO_ECHO', 'SONAR_UNITS_PER_M', 'SonarPose', 'robot_named', 'sonar_range_m',
           'sonar_range_raw', 'voltage_raw', 'voltage_v']

SONAR_UNITS_PER_M = 1476
SONAR_NO_ECHO = 32766
HEADING_HOME_ADDRESS = 0x31


class DriveKind(enum.Enum):
    SYNCHRO = 'synchro'              # B21r: all wheels steer together, the body turns with them
    DIFFERENTIAL = 'differential'    # ATRV-Jr: skid steering, left/right sides


@dataclasses.dataclass(frozen=True)
class SonarPose:
    """Where one sonar sits: its id in SONAR_REPORT, position (m) and pointing angle (rad)."""

    sonar_id: int
    x: float
    y: float
    z: float
    yaw: float
    ring: str = 'body'


@dataclasses.dataclass(frozen=True)
class BumperPanel:
    """One bumper panel: its DIO address, ring and the direction it faces (rad)."""

    address: int
    ring: str
    index: int
    yaw: float


@dataclasses.dataclass(frozen=True)
class RobotParams:
    """Everything robot-specific the rFLEX driver and emulator need."""

    name: str
    drive: DriveKind
    units_per_m: float
    units_per_rad: float
    sonars: tuple[SonarPose, ...]
    bumpers: tuple[BumperPanel, ...] = ()
    trans_torque: int = 30000          # Player's STD_TRANS_TORQUE
    rot_torque: int = 35000            # Player's STD_ROT_TORQUE
    trans_accel: float = 0.7           # m/s^2, DLu's default command acceleration
    rot_accel_counts: int = 100000     # Player's STD_ROT_ACC (counts/s^2)
    voltage_offset: float = 1.2

    @property
    def rot_accel(self) -> float:
        """The default rotational acceleration in rad/s^2."""
        return self.rot_accel_counts / self.units_per_rad

    # -- conversions ----------------------------------------------------------------------------
    def counts_from_m(self, metres: float) -> int:
        """Metres to the distance counter's units (rounded).

        :param metres: a distance or speed in m (or m/s).
        """
        return int(round(metres * self.units_per_m))

    def counts_from_rad(self, radians: float) -> int:
        """Radians to the bearing counter's units (rounded).

        :param radians: an angle or turn rate in rad (or rad/s).
        """
        return int(round(radians * self.units_per_rad))

    def m_from_counts(self, counts: float) -> float:
        """Distance-counter units to metres.

        :param counts: a count or a count rate.
        """
        return counts / self.units_per_m

    def rad_from_counts(self, counts: float) -> float:
        """Bearing-counter units to radians.

        :param counts: a count or a count rate.
        """
        return counts / self.units_per_rad

    def sonar_index(self, sonar_id: int) -> int | None:
        """Position of ``sonar_id`` in :attr:`sonars`, or None for an id this robot lacks.

        :param sonar_id: the id in SONAR_REPORT, ``bank * 16 + index``.
        """
        return self._sonar_indices.get(sonar_id)

    @functools.cached_property
    def _sonar_indices(self) -> dict[int, int]:
        return {pose.sonar_id: i for i, pose in enumerate(self.sonars)}

    def bumper(self, address: int) -> BumperPanel | None:
        """The panel at DIO ``address``, or None.

        :param address: the DIO address of a DIO_REPORT.
        """
        return next((panel for panel in self.bumpers if panel.address == address), None)


def sonar_range_m(raw: int) -> float:
    """Raw sonar range to metres (1476 units a metre).

    :param raw: the range of a SONAR_REPORT triplet; :data:`SONAR_NO_ECHO` (or more) is ``inf``.
    """
    return math.inf if raw >= SONAR_NO_ECHO else raw / SONAR_UNITS_PER_M


def sonar_range_raw(metres: float) -> int:
    """Metres to a raw range.

    :param metres: the range; ``inf``, NaN, negative or out of range gives :data:`SONAR_NO_ECHO`.
    """
    if not math.isfinite(metres) or metres < 0:
        return SONAR_NO_ECHO
    return min(int(round(metres * SONAR_UNITS_PER_M)), SONAR_NO_ECHO)


def voltage_v(raw: int, offset: float = 1.2) -> float:
    """SYS_STATUS raw voltage to volts (DLu: ``raw / 100 + 1.2``).

    :param raw: the reply's voltage field; 0 means not measured and gives 0.0 V.
    :param offset: volts added (the robot's ``voltage_offset``).
    """
    return 0.0 if raw == 0 else raw / 100.0 + offset


def voltage_raw(volts: float, offset: float = 1.2) -> int:
    """Volts to the raw SYS_STATUS value (for the emulator); never below 0.

    :param volts: the battery voltage.
    :param offset: volts the driver will add back.
    """
    return max(0, int(round((volts - offset) * 100.0)))


def _ring(first_bank: int, per_bank: tuple[int, ...], start_deg: float, radius: float,
          z: float, ring: str) -> tuple[SonarPose, ...]:
    poses: list[SonarPose] = []
    for bank, count in enumerate(per_bank, start=first_bank):
        for index in range(count):
            yaw = math.radians(start_deg - 15.0 * len(poses))
            poses.append(SonarPose(bank * 16 + index, radius * math.cos(yaw),
                                   radius * math.sin(yaw), z, yaw, ring))
    return tuple(poses)


def _b21r_bumpers() -> tuple[BumperPanel, ...]:
    panels = []
    for ring, count, first in (('body', 6, 0x40), ('base', 8, 0x46)):
        wedge = 2 * math.pi / count
        panels += [BumperPanel(first + i, ring, i, wedge * (2.5 - i)) for i in range(count)]
    return tuple(panels)


# ATRV-Jr sonars, DLu atrvjr_config.h: (x mm, y mm, yaw rad) for banks of 5, 8, 5, 8.
_ATRVJR_SONARS = (
    (-334.95, -104.39, -2.617993), (-340.41, -49.91, -2.879793), (-347.06, 0.0, math.pi),
    (-340.41, 49.91, 2.879793), (-334.95, 104.39, 2.617993),
    (230.23, 175.0, 0.785398), (172.49, 178.6, 1.047197), (117.2, 181.1, 1.308997),
    (72.26, 181.1, 1.570796), (-72.26, 181.1, 1.570796), (-117.2, 181.1, 1.832595),
    (-172.49, 178.6, 2.094395), (-230.23, 175.0, 2.356194),
    (296.2, 103.6, 0.523599), (301.5, 49.5, 0.261799), (308.1, 0.0, 0.0),
    (301.5, -49.5, -0.261799), (296.2, -103.6, -0.523599),
    (230.23, -175.0, -0.785398), (172.49, -178.6, -1.047197), (117.2, -181.1, -1.308997),
    (72.26, -181.1, -1.570796), (-72.26, -181.1, -1.570796), (-117.2, -181.1, -1.832595),
    (-172.49, -178.6, -2.094395), (-230.23, -175.0, -2.356194),
)


def _atrvjr_sonars() -> tuple[SonarPose, ...]:
    ids = [bank * 16 + i for bank, count in enumerate((5, 8, 5, 8)) for i in range(count)]
    return tuple(SonarPose(sid, x / 1000.0, y / 1000.0, 0.36, yaw)
                 for sid, (x, y, yaw) in zip(ids, _ATRVJR_SONARS))


B21R = RobotParams(
    name='B21r', drive=DriveKind.SYNCHRO, units_per_m=103000, units_per_rad=35000,
    sonars=_ring(0, (4,) * 6, 180.0, 0.25, 0.055, 'body') + _ring(6, (3,) * 8, 90.0, 0.26,
                                                                  -0.06, 'base'),
    bumpers=_b21r_bumpers())

ATRV_JR = RobotParams(
    name='ATRVJr', drive=DriveKind.DIFFERENTIAL, units_per_m=90810, units_per_rad=37000,
    sonars=_atrvjr_sonars())

#: The appendix's name of the B21r (guide 10.1.5).
B21IR = dataclasses.replace(B21R, name='B21ir')

#: Pluto's ATRV2: skid steering, the ATRV-Jr's rFLEX factors and sonars (see the module's doc).
ATRV2 = dataclasses.replace(ATRV_JR, name='ATRV2')

#: The robots by the names rflex-config.xml uses for ``type``.
ROBOTS: dict[str, RobotParams] = {r.name: r for r in (B21R, B21IR, ATRV_JR, ATRV2)}

#: Body length x width (m) and track width (m) per type.  B21r: a cylinder 0.52 m across (RWI);
#: ATRV-Jr: 0.80 x 0.55 m (RWI); ATRV2: 1.05 x 0.65 m, the ATRV-2's published size (approximate:
#: no datasheet is in the seeds); the track widths are estimates (the rFLEX reports none).
BODY_M: dict[str, tuple[float, float, float]] = {'B21r': (0.52, 0.52, 0.5), 'B21ir': (0.52, 0.52, 0.5),
                                                 'ATRVJr': (0.80, 0.55, 0.42), 'ATRV2': (1.05, 0.65, 0.55)}


def robot_named(name: str) -> RobotParams:
    """The robot of an rflex-config ``type``.

    :param name: ``B21r``, ``B21ir``, ``ATRVJr`` or ``ATRV2``.
    :raises KeyError: for a robot type not in :data:`ROBOTS`.
    """
    try:
        return ROBOTS[name]
    except KeyError:
        raise KeyError(f'unknown rFLEX robot type {name!r}; known: {", ".join(ROBOTS)}') from None
