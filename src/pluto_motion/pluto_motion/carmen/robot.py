"""CARMEN's robot module (Programming with CARMEN 3.1.5, 4): its laser messages and the velocity
command.

``carmen_robot_subscribe_frontlaser_message`` / ``_rearlaser_`` give each scan with the laser's and
the robot's pose in the odometry frame at the scan's time, as CARMEN's robot does by interpolating
the base's odometry (:class:`pluto_nav.pose_history.PoseHistory`, the last 5 s); a scan the
odometry does not cover (before its oldest sample kept, more than 0.2 s after its newest) gives no
message.
``carmen_robot_velocity_command`` goes through the driveModule, the last-mile guard of Pluto's chain
(4: never straight to the base): sonar-protected velocity control (cmdFlags 10), which the
drive stops after 4 s without a new command (CARMEN's robot has the same kind of timeout).
"""

from __future__ import annotations

import math
from typing import Any

from wurde_core.errors import InvalidValueError
from wurde_core.interfaces import RangeFinder

from ..drive_proxy import DriveProxy
import pluto_motion.carmen.convert as convert  # the module itself, not the package (whose __init__ imports this one)
from .connection import connection
from .ipc import Handler, mode
from .messages import carmen_robot_laser_message

#: Seconds the first velocity command waits for the driveModule's reader.
DRIVE_MATCH_S = 20.0

__all__ = ['carmen_robot_subscribe_frontlaser_message', 'carmen_robot_subscribe_rearlaser_message',
           'carmen_robot_velocity_command']


def _robot_laser(name: str, key: str, laser: Any, handler: Handler | None, how: int) -> Any:
    ipc = connection()
    how = mode(how)
    stream = ipc.streams[key]
    info: Any = None                        # unsubscribing: no feed, nothing is filled
    if how:
        ipc.odometry_feed()
        info = ipc.feed(stream, lambda: RangeFinder(stream), name, False).obj.info

    def fill(msg: Any, d: Any) -> bool:
        return convert.robot_laser(msg, d, info, ipc.odometry, ipc.velocity)
    return ipc.subscribe(name, carmen_robot_laser_message, stream, fill, laser, handler, how)


def carmen_robot_subscribe_frontlaser_message(laser: carmen_robot_laser_message | None,
                                              handler: Handler | None, subscribe_how: int) -> Any:
    """The front laser's scans with the laser's and the robot's odometry pose at scan time.

    :param laser: the message to fill on each scan the odometry covers (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _robot_laser('carmen_robot_frontlaser', 'frontlaser', laser, handler, subscribe_how)


def carmen_robot_subscribe_rearlaser_message(laser: carmen_robot_laser_message | None,
                                             handler: Handler | None, subscribe_how: int) -> Any:
    """The rear laser's scans with the laser's and the robot's odometry pose at scan time.

    :param laser: the message to fill on each scan the odometry covers (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _robot_laser('carmen_robot_rearlaser', 'rearlaser', laser, handler, subscribe_how)


def carmen_robot_velocity_command(tv: float, rv: float) -> int:
    """Drive at ``tv`` m/s and ``rv`` rad/s through the driveModule's guard; 0 (sent, or held
    until the driveModule is heard).

    :param tv: the linear velocity (m/s), finite; the driveModule limits it.
    :param rv: the angular velocity (rad/s), finite; the driveModule limits it.
    :raises InvalidValueError: a value that is not finite.
    """
    if not (math.isfinite(tv) and math.isfinite(rv)):
        raise InvalidValueError(f'carmen_robot_velocity_command({tv}, {rv}): finite m/s and rad/s')
    ipc = connection()
    drive = ipc.links.get('drive')
    if drive is None:
        drive = ipc.links['drive'] = DriveProxy(ipc.manager)
        drive.start_activity()                      # a released drive takes commands again
        ipc.collectors.append(drive.update)
        # The first command waits (at most DRIVE_MATCH_S) until the driveModule reads commands
        # and can drive the base (its status's ready: it hears the sonar, the base hears it), as
        # CARMEN's IPC delivers to the base once connected: a program that drives for 2 s right
        # after its first command must not spend them on discovery (held commands would go out
        # only when matched, the newest alone; a drive without sonar stops the robot).
        drive.wait_for(lambda p: p.command.peers('request') > 0 and p.ready, DRIVE_MATCH_S)
    drive.velocity(float(tv), float(rv), sonar=True)
    return 0
