"""What ``ros_inputs`` is told: the robot's side as ROS 2 parameters, read once at start.

A ROS user sets them as for any node (``--ros-args -p scan_topic:=/front/scan``, or a
``--params-file``); ``ros2 param get`` shows them.  They are read-only: topics and frames are
chosen once, as a driver's port is.  Topic names may be relative: they resolve in the node's
namespace.  The parameters are the robot's topics (``scan_topic``, ``odom_topic``,
``cmd_vel_topic``), its frames (``base_frame``, ``laser_frame``), the limits commands are clamped
to and the drive info reports, the command watchdog and resend rate, and how long topics may be
silent; docs/wurde-drivers.md ("ros_inputs.settings") gives each with its default and unit.

A value of the wrong type or out of range ends the program with status 2 and
``ros_inputs: parameter NAME: reason`` on stderr.  A new parameter needs its default here, in the
docs page's table and in config/README.md's.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from rcl_interfaces.msg import ParameterDescriptor
from rclpy.exceptions import ParameterException
from wurde_idl.errors import ConfigError

__all__ = ['PARAMETERS', 'Settings', 'read_settings']


@dataclasses.dataclass(frozen=True)
class Settings:
    """The parameters' values (table above)."""

    scan_topic: str = 'scan'
    odom_topic: str = 'odom'
    cmd_vel_topic: str = 'cmd_vel'
    base_frame: str = ''
    laser_frame: str = ''
    max_tv: float = 1.0
    max_rv: float = 1.5
    tv_accel: float = 0.5
    rv_accel: float = 1.5
    wheel_base: float = 0.5
    command_timeout: float = 1.0
    cmd_rate: float = 10.0
    silent_after: float = 1.0
    max_held_scans: int = 10


#: name -> (description, smallest allowed value or None for a text).
PARAMETERS: dict[str, tuple[str, float | None]] = {
    'scan_topic': ('the robot\'s sensor_msgs/LaserScan topic', None),
    'odom_topic': ('the robot\'s nav_msgs/Odometry topic', None),
    'cmd_vel_topic': ('the topic where the robot\'s base takes geometry_msgs/Twist', None),
    'base_frame': ('the robot\'s body frame (\'\': each Odometry\'s child_frame_id)', None),
    'laser_frame': ('the laser\'s frame (\'\': each scan\'s header.frame_id)', None),
    'max_tv': ('m/s: largest linear velocity sent', 1e-3),
    'max_rv': ('rad/s: largest angular velocity sent', 1e-3),
    'tv_accel': ('m/s^2: linear acceleration reported in the drive info', 1e-3),
    'rv_accel': ('rad/s^2: angular acceleration reported in the drive info', 1e-3),
    'wheel_base': ('m: the drive info\'s wheel base', 1e-3),
    'command_timeout': ('s without a command that stop the robot', 0.05),
    'cmd_rate': ('Hz: a moving command is sent again this often', 0.5),
    'silent_after': ('s without odometry or scans that are logged as silence', 0.05),
    'max_held_scans': ('scans held while the laser\'s mount is not known', 0),
}


def _coerce(name: str, value: Any, default: Any, minimum: float | None) -> Any:
    where = f'parameter {name}'
    if isinstance(default, str):
        if not isinstance(value, str):
            raise ConfigError(where, None, f'{value!r} is not a text')
        return value.strip()
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(where, None, f'{value!r} is not a number')
    if isinstance(default, int) and not float(value).is_integer():
        raise ConfigError(where, None, f'{value!r} is not a whole number')
    number = type(default)(value)
    if not math.isfinite(number) or (minimum is not None and number < minimum):
        raise ConfigError(where, None, f'{value!r} is out of range (at least {minimum:g})')
    return number


def read_settings(node: Any) -> Settings:
    """Declare the parameters on ``node`` (read-only; overrides from ``--ros-args``) and read them.

    :raises ConfigError: ``parameter NAME: reason`` for a value of the wrong type or range.
    """
    defaults = Settings()
    values = {}
    for name, (description, minimum) in PARAMETERS.items():
        default = getattr(defaults, name)
        descriptor = ParameterDescriptor(description=description, read_only=True, dynamic_typing=True)
        try:
            value = node.declare_parameter(name, default, descriptor).value
        except ParameterException as error:
            raise ConfigError(f'parameter {name}', None, str(error)) from error
        values[name] = _coerce(name, value, default, minimum)
    return Settings(**values)
