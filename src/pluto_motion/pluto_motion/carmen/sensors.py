"""CARMEN's sensor subscriptions (Programming with CARMEN 3.1): the base's odometry, sonar,
bumpers and IR, the front and rear lasers.

Each is ``carmen_X_subscribe_Y_message(msg, handler, subscribe_how)`` on one of our streams
(``B`` the base, ``F``/``R`` the front and rear lasers, named at carmen_ipc_initialize):

=========================================== ======================= =========================
CARMEN message                              our stream              interface
=========================================== ======================= =========================
carmen_base_odometry_message                ``BMotion``             Egomotion
carmen_base_sonar_message                   ``BSonar``              RangeFinder
carmen_base_bumper_message                  ``BBumpers``            Bumper
carmen_base_ir_message                      ``BIR``                 RangeFinder
carmen_laser_laser_message (front / rear)   ``F`` / ``R``           RangeFinder
=========================================== ======================= =========================

A laser's RangeFinder is in robot order, counter-clockwise from the laser's own right (3.1.4);
a laser mounted backwards therefore runs from the robot's +90° through 180° to -90°, CARMEN's
rear-laser order.  An upside-down laser is turned round by its driver (``inverted``), so its
messages come in the same order as an upright one's.
"""

from __future__ import annotations

from typing import Any

from wurde_core.interfaces import Bumper, Egomotion, RangeFinder

import pluto_motion.carmen.convert as convert  # the module itself, not the package (whose __init__ imports this one)
from .connection import connection
from .ipc import Handler, mode
from .messages import (carmen_base_bumper_message, carmen_base_ir_message, carmen_base_odometry_message,
                       carmen_base_sonar_message, carmen_laser_laser_message)

__all__ = ['carmen_base_subscribe_bumper_message', 'carmen_base_subscribe_ir_message',
           'carmen_base_subscribe_odometry_message', 'carmen_base_subscribe_sonar_message',
           'carmen_laser_subscribe_frontlaser_message', 'carmen_laser_subscribe_rearlaser_message']


def _subscribe(name: str, message_type: type, interface: Any, stream: str, fill: Any, msg: Any,
               handler: Handler | None, how: int, *, with_info: bool = False) -> Any:
    ipc = connection()
    how = mode(how)
    if how:
        feed = ipc.feed(stream, lambda: interface(stream), name, False)
        if with_info:
            info = feed.obj.info
            return ipc.subscribe(name, message_type, stream, lambda m, d: fill(m, d, info), msg, handler, how)
    return ipc.subscribe(name, message_type, stream, fill, msg, handler, how)


def _base(suffix: str) -> str:
    return f'{connection().streams["base"]}{suffix}'


def carmen_base_subscribe_odometry_message(odometry: carmen_base_odometry_message | None,
                                           handler: Handler | None, subscribe_how: int) -> Any:
    """3.1.1: the raw odometry (x, y, theta since the base started), tv, rv, acceleration.

    :param odometry: the message to fill on each odometry sample (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _subscribe('carmen_base_odometry', carmen_base_odometry_message, Egomotion, _base('Motion'),
                      convert.odometry, odometry, handler, subscribe_how)


def carmen_base_subscribe_sonar_message(sonar: carmen_base_sonar_message | None,
                                        handler: Handler | None, subscribe_how: int) -> Any:
    """3.1.2: one range per transducer and each transducer's pose on the robot.

    :param sonar: the message to fill on each sonar reading (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _subscribe('carmen_base_sonar', carmen_base_sonar_message, RangeFinder, _base('Sonar'),
                      convert.sonar, sonar, handler, subscribe_how, with_info=True)


def carmen_base_subscribe_bumper_message(bumper: carmen_base_bumper_message | None,
                                         handler: Handler | None, subscribe_how: int) -> Any:
    """3.1.3: range[i] 1.0 while bumper i is pressed, 0.0 while it is free.

    :param bumper: the message to fill on each bumper reading (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _subscribe('carmen_base_bumper', carmen_base_bumper_message, Bumper, _base('Bumpers'),
                      convert.bumper, bumper, handler, subscribe_how)


def carmen_base_subscribe_ir_message(ir: carmen_base_ir_message | None, handler: Handler | None,
                                     subscribe_how: int) -> Any:
    """3.1.3: one range per infra-red sensor (a RangeFinder ``<base>IR``; our bases have none).

    :param ir: the message to fill on each reading (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _subscribe('carmen_base_ir', carmen_base_ir_message, RangeFinder, _base('IR'),
                      lambda m, d: convert.ranges(m, d, 'num_irs'), ir, handler, subscribe_how)


def _laser(name: str, key: str, laser: Any, handler: Handler | None, how: int) -> Any:
    stream = connection().streams[key]
    return _subscribe(name, carmen_laser_laser_message, RangeFinder, stream,
                      lambda m, d: convert.ranges(m, d, 'num_readings'), laser, handler, how)


def carmen_laser_subscribe_frontlaser_message(laser: carmen_laser_laser_message | None,
                                              handler: Handler | None, subscribe_how: int) -> Any:
    """3.1.4: the front laser's ranges (m), -90° to +90° counter-clockwise.

    :param laser: the message to fill on each scan (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _laser('carmen_laser_frontlaser', 'frontlaser', laser, handler, subscribe_how)


def carmen_laser_subscribe_rearlaser_message(laser: carmen_laser_laser_message | None,
                                             handler: Handler | None, subscribe_how: int) -> Any:
    """3.1.4: the rear laser's ranges (m), +90° through 180° to -90° of the robot.

    :param laser: the message to fill on each scan (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _laser('carmen_laser_rearlaser', 'rearlaser', laser, handler, subscribe_how)
