"""wurde_core: the WURDE programming model on rclpy.

Declare an object of a device's type, register it, and use it; where it runs and how the bytes
move is hidden::

    from wurde_core import CommsManager, RunState
    from wurde_core.interfaces import Foo

    manager = CommsManager("FooClient")
    foo = Foo("Bar")
    manager.register_consumer(foo)
    while manager.run_update() == RunState.RUN:
        while foo.new_data():
            foo.get_next_data()
    manager.clean_up()
"""

from .comms_manager import CommsManager
from .enums import ConnectionStrategy, LockMode, ProcessLocale, ProcessType, RunState, StatusMode
from .errors import (ConfigError, DirectionError, LockedError, NotRegisteredError, OptionError,
                     RegistrationError, UnknownInterfaceError, WurdeError)
from .geometry import CVector, PlanarPoint, PlanarPose, Point, Point3D, Pose, Pose3D, PVector
from .logger import Logger, ModuleLogger, g_debug, g_error, g_fatal, g_info, g_notice, g_warn
from .naming import stream_name, topic
from .robot_object import RobotObject
from .role_config import RoleConfiguration, global_configuration
from .timestamp import Time, Timestamp
from .trigger import Trigger
from .writable import Writable

__all__ = [
    'CVector', 'CommsManager', 'ConfigError', 'ConnectionStrategy', 'DirectionError', 'LockMode',
    'LockedError', 'Logger', 'ModuleLogger', 'NotRegisteredError', 'OptionError', 'PVector',
    'PlanarPoint', 'PlanarPose', 'Point', 'Point3D', 'Pose', 'Pose3D', 'ProcessLocale', 'ProcessType',
    'RegistrationError', 'RobotObject', 'RoleConfiguration', 'RunState', 'StatusMode', 'Time',
    'Timestamp', 'Trigger', 'UnknownInterfaceError', 'Writable', 'WurdeError', 'g_debug', 'g_error',
    'g_fatal', 'g_info', 'g_notice', 'g_warn', 'global_configuration', 'stream_name', 'topic',
]
