"""CARMEN's message structures and constants, with CARMEN's names, fields and units.

Programming with CARMEN 3.0.1 (subscribe modes), 3.1.1–3.1.4 (odometry, sonar, bumper, IR,
laser), 4.2 (localize initialization), 4.3 (autonomous-stopped reasons), 5.4 (navigator maps).
Units as CARMEN's: metres, radians, m/s, rad/s; ``timestamp`` in seconds of the time the data was
acquired (the supplier's header stamp), ``host`` the origin of the data (the supplying module's
name, which is what our headers carry; not cut to CARMEN's 10 characters).  Arrays are Python
lists of the message's own length (``range`` of a bumper message is not padded to 32).  The
robot, localize and navigator structures that the seed names without printing them follow
CARMEN 0.7's headers.
"""

# CARMEN's own names: lower-case types ending in _t / _message, as a ported program spells them.
# ruff: noqa: N801

from __future__ import annotations

import dataclasses
import enum


class carmen_subscribe_t(enum.IntEnum):
    """How to subscribe (3.0.1)."""

    CARMEN_UNSUBSCRIBE = 0
    CARMEN_SUBSCRIBE_LATEST = 1
    CARMEN_SUBSCRIBE_ALL = 2


CARMEN_UNSUBSCRIBE = carmen_subscribe_t.CARMEN_UNSUBSCRIBE
CARMEN_SUBSCRIBE_LATEST = carmen_subscribe_t.CARMEN_SUBSCRIBE_LATEST
CARMEN_SUBSCRIBE_ALL = carmen_subscribe_t.CARMEN_SUBSCRIBE_ALL


class carmen_navigator_reason_t(enum.IntEnum):
    """Why autonomous motion stopped (4.3); UNKNOWN is every other end (ours: a goal not reached)."""

    CARMEN_NAVIGATOR_GOAL_REACHED_v = 0
    CARMEN_NAVIGATOR_USER_STOPPED_v = 1
    CARMEN_NAVIGATOR_UNKNOWN_v = 2


CARMEN_NAVIGATOR_GOAL_REACHED_v = carmen_navigator_reason_t.CARMEN_NAVIGATOR_GOAL_REACHED_v
CARMEN_NAVIGATOR_USER_STOPPED_v = carmen_navigator_reason_t.CARMEN_NAVIGATOR_USER_STOPPED_v
CARMEN_NAVIGATOR_UNKNOWN_v = carmen_navigator_reason_t.CARMEN_NAVIGATOR_UNKNOWN_v


class carmen_navigator_map_t(enum.IntEnum):
    """The maps ``carmen_navigator_get_map`` may be asked for (5.4)."""

    CARMEN_NAVIGATOR_MAP_v = 0
    CARMEN_NAVIGATOR_ENTROPY_v = 1
    CARMEN_NAVIGATOR_COST_v = 2
    CARMEN_NAVIGATOR_UTILITY_v = 3
    CARMEN_LOCALIZE_LMAP_v = 4
    CARMEN_LOCALIZE_GMAP_v = 5


CARMEN_NAVIGATOR_MAP_v = carmen_navigator_map_t.CARMEN_NAVIGATOR_MAP_v
CARMEN_NAVIGATOR_ENTROPY_v = carmen_navigator_map_t.CARMEN_NAVIGATOR_ENTROPY_v
CARMEN_NAVIGATOR_COST_v = carmen_navigator_map_t.CARMEN_NAVIGATOR_COST_v
CARMEN_NAVIGATOR_UTILITY_v = carmen_navigator_map_t.CARMEN_NAVIGATOR_UTILITY_v
CARMEN_LOCALIZE_LMAP_v = carmen_navigator_map_t.CARMEN_LOCALIZE_LMAP_v
CARMEN_LOCALIZE_GMAP_v = carmen_navigator_map_t.CARMEN_LOCALIZE_GMAP_v

#: Initialization distributions (4.2; localize_messages.h's values).
CARMEN_INITIALIZE_UNIFORM = 1
CARMEN_INITIALIZE_GAUSSIAN = 2


@dataclasses.dataclass
class carmen_point_t:
    """A pose: x, y in m, theta in rad."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


@dataclasses.dataclass
class carmen_traj_point_t:
    """A pose with velocities: t_vel in m/s, r_vel in rad/s."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    t_vel: float = 0.0
    r_vel: float = 0.0


@dataclasses.dataclass
class carmen_base_odometry_message:
    """3.1.1: raw odometry since the base started; tv, rv its velocities."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    tv: float = 0.0
    rv: float = 0.0
    acceleration: float = 0.0
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_base_sonar_message:
    """3.1.2: one range per transducer, each transducer's pose on the robot."""

    num_sonars: int = 0
    range: list[float] = dataclasses.field(default_factory=list)
    sonar_offsets: list[carmen_point_t] = dataclasses.field(default_factory=list)
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_base_bumper_message:
    """3.1.3 as printed (its count is called ``num_sonars``): ``range[i]`` is 1.0 while bumper i
    is pressed, 0.0 while it is free (the seed gives no values)."""

    num_sonars: int = 0
    range: list[float] = dataclasses.field(default_factory=list)
    timestamp: float = 0.0
    host: str = ''

    @property
    def num_bumpers(self) -> int:
        """The count, by what it counts."""
        return self.num_sonars


@dataclasses.dataclass
class carmen_base_ir_message:
    """3.1.3: one range (m) per infra-red sensor."""

    num_irs: int = 0
    range: list[float] = dataclasses.field(default_factory=list)
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_laser_laser_message:
    """3.1.4: ranges (m), counter-clockwise from the laser's right (-90°) to its left (+90°)."""

    num_readings: int = 0
    range: list[float] = dataclasses.field(default_factory=list)
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_robot_laser_message:
    """3.1.5 (robot's laser message): the scan with the laser's pose (x, y, theta) and the robot's
    (odom_x, odom_y, odom_theta) in the odometry frame at the scan's time, and the robot's tv, rv."""

    num_readings: int = 0
    range: list[float] = dataclasses.field(default_factory=list)
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    odom_x: float = 0.0
    odom_y: float = 0.0
    odom_theta: float = 0.0
    tv: float = 0.0
    rv: float = 0.0
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_localize_globalpos_message:
    """The localized pose in the map frame, its standard deviations, the odometry pose of the same
    moment and whether localize has converged (an estimator holds the pose)."""

    globalpos: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    globalpos_std: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    odometrypos: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    globalpos_xy_cov: float = 0.0
    converged: int = 0
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_localize_particle_message:
    """Localize's particles (3.0.2); our localization keeps none."""

    num_particles: int = 0
    particles: list[carmen_point_t] = dataclasses.field(default_factory=list)
    globalpos: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    globalpos_std: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_navigator_status_message:
    """The navigator's state: autonomous, whether a goal is set, the goal and the robot."""

    autonomous: int = 0
    goal_set: int = 0
    goal: carmen_point_t = dataclasses.field(default_factory=carmen_point_t)
    robot: carmen_traj_point_t = dataclasses.field(default_factory=carmen_traj_point_t)
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_navigator_plan_message:
    """The navigator's planned path from the robot to the goal."""

    path: list[carmen_traj_point_t] = dataclasses.field(default_factory=list)
    path_length: int = 0
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_navigator_autonomous_stopped_message:
    """4.3: autonomous motion ended, and why."""

    reason: carmen_navigator_reason_t = CARMEN_NAVIGATOR_UNKNOWN_v
    timestamp: float = 0.0
    host: str = ''


@dataclasses.dataclass
class carmen_map_config_t:
    """A grid's size in cells, its resolution (m per cell) and its map's name."""

    x_size: int = 0
    y_size: int = 0
    resolution: float = 0.0
    map_name: str = ''


@dataclasses.dataclass
class carmen_navigator_map_message:
    """5.4: ``size`` cells of ``data``, CARMEN's column-major order (x slowest): cell (x, y) is
    ``data[x * config.y_size + y]``; occupancy 0..1, -1 unknown."""

    data: list[float] = dataclasses.field(default_factory=list)
    size: int = 0
    config: carmen_map_config_t = dataclasses.field(default_factory=carmen_map_config_t)
    map_type: carmen_navigator_map_t = CARMEN_NAVIGATOR_MAP_v
    timestamp: float = 0.0
    host: str = ''


def copy_into(target: object, source: object) -> None:
    """Fill ``target`` with ``source``'s fields in place (a program's own message memory, 3.0.1).

    :param target: the program's message, of ``source``'s type.
    :param source: a message (a dataclass) whose fields are copied, not deep-copied.
    """
    for field in dataclasses.fields(source):  # type: ignore[arg-type]
        setattr(target, field.name, getattr(source, field.name))
