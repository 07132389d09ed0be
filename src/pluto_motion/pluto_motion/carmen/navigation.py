"""CARMEN's localize and navigator calls (Programming with CARMEN 3.0.2, 3.2, 4.2, 4.2.1, 4.3,
5.4) on Pluto's localization and our CARMEN navigator and map server.

- localize: the globalpos message is the localModule's ``Localization/Pose`` (converged while the
  poseModule or slamModule holds the pose); ``carmen_localize_initialize_gaussian_command`` writes
  the mean as a robot pose (setter -1) with the covariance diag(std²) to ``Localization/Post_Pose``,
  stopping and restarting the poseModule around it as Pluto 7.1 says (:mod:`.initialize`); the
  uniform command is refused, as CARMEN's localize does (4.2).
- navigator: the ``navigator`` program's NavigatorTransport (set_goal, set_goal_place, go, stop),
  its status and plan; autonomous_stopped is the event :mod:`.stops` reads from the status.
- ``carmen_navigator_get_map``: the map server's grid (CARMEN_NAVIGATOR_MAP_v); our navigator keeps
  no entropy, cost or utility map, and localize no likelihood maps.

Queries wait up to :data:`QUERY_WAIT_S` for the answer and return a new message, or ``None``.
Commands sent before the navigator or the localModule is heard are held and sent once it is
(the navigator: once its reader is matched and its first status has come).
"""

from __future__ import annotations

import collections
import math
from typing import Any

import numpy as np

from wurde_core import Point
from wurde_core.errors import InvalidValueError
from wurde_core.interfaces import LocalizationPose, MapServer, Navigator

from pluto_nav.streams import POSE, STREAMS

import pluto_motion.carmen.convert as convert  # the module itself, not the package (whose __init__ imports this one)
from .connection import connection
from .initialize import Initializer
from .ipc import CarmenIpc, Feed, Handler, mode, warn
from .messages import (CARMEN_NAVIGATOR_MAP_v, carmen_localize_globalpos_message,
                       carmen_navigator_autonomous_stopped_message, carmen_navigator_map_message,
                       carmen_navigator_map_t, carmen_navigator_plan_message,
                       carmen_navigator_status_message, carmen_point_t)
from .stops import StopWatch

__all__ = ['QUERY_WAIT_S', 'carmen_localize_initialize_gaussian_command',
           'carmen_localize_initialize_uniform_command', 'carmen_localize_query_globalpos',
           'carmen_localize_query_particles', 'carmen_localize_subscribe_globalpos_message',
           'carmen_navigator_get_map', 'carmen_navigator_go', 'carmen_navigator_query_plan',
           'carmen_navigator_query_status', 'carmen_navigator_set_goal', 'carmen_navigator_set_goal_place',
           'carmen_navigator_stop', 'carmen_navigator_subscribe_autonomous_stopped_message',
           'carmen_navigator_subscribe_plan_message', 'carmen_navigator_subscribe_status_message']

#: Longest wait of a query for its answer (a stream discovered on a loaded machine: seconds).
QUERY_WAIT_S = 20.0
STOPPED = 'carmen_navigator_autonomous_stopped'


# -- localize ---------------------------------------------------------------------------------------
def _pose_feed(ipc: CarmenIpc, user: str, every: bool = False) -> Feed:
    ipc.odometry_feed()
    stream = STREAMS[POSE]
    return ipc.feed(stream, lambda: LocalizationPose(stream), user, every)


def carmen_localize_subscribe_globalpos_message(globalpos: carmen_localize_globalpos_message | None,
                                                handler: Handler | None, subscribe_how: int) -> Any:
    """The localized pose (map frame), its deviations and the odometry pose of the same moment.

    :param globalpos: the message to fill on each pose (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    ipc = connection()
    how = mode(subscribe_how)
    name = 'carmen_localize_globalpos'
    if how:
        _pose_feed(ipc, name)
    return ipc.subscribe(name, carmen_localize_globalpos_message, STREAMS[POSE],
                         lambda m, d: convert.globalpos(m, d, ipc.odometry), globalpos, handler, how)


def carmen_localize_query_globalpos() -> carmen_localize_globalpos_message | None:
    """3.0.2: the newest globalpos as a new message (None: none within :data:`QUERY_WAIT_S`)."""
    ipc = connection()
    feed = _pose_feed(ipc, '_query')
    if not ipc.wait_for(lambda: feed.latest is not None, QUERY_WAIT_S):
        return None
    msg = carmen_localize_globalpos_message()
    convert.globalpos(msg, feed.latest, ipc.odometry)
    return msg


def carmen_localize_query_particles() -> None:
    """3.0.2's particle query: our localization is a Kalman filter and keeps no particles; None."""
    warn('localize keeps no particles (Pluto\'s localization is a Kalman filter); see the globalpos '
         'message\'s globalpos_std')
    return None


def carmen_localize_initialize_gaussian_command(mean: carmen_point_t, std: carmen_point_t) -> int:
    """4.2: put the robot at ``mean`` (m, rad, map frame) with deviations ``std``; 0 (sent, or held
    until the localModule is heard).

    :param mean: the pose (x, y in m, theta in rad, map frame).
    :param std: its standard deviations (m, m, rad), each at least 0.
    :raises InvalidValueError: a value that is not finite, or a negative deviation.
    """
    values = [mean.x, mean.y, mean.theta, std.x, std.y, std.theta]
    if not all(math.isfinite(v) for v in values) or min(values[3:]) < 0:
        raise InvalidValueError(f'carmen_localize_initialize_gaussian_command: mean {mean}, std {std}: '
                                'finite values and deviations >= 0')
    ipc = connection()
    initializer = ipc.links.get('localize')
    if initializer is None:
        initializer = ipc.links['localize'] = Initializer(ipc.manager)
        ipc.collectors.append(initializer.update)
    initializer.start((mean.x, mean.y, mean.theta), np.diag([std.x ** 2, std.y ** 2, std.theta ** 2]))
    return 0


def carmen_localize_initialize_uniform_command() -> int:
    """4.2: "not currently supported by localize itself", nor by ours (no global localization); -1."""
    warn('localize does not support a uniform initialization (Programming with CARMEN 4.2); use '
         'carmen_localize_initialize_gaussian_command')
    return -1


# -- navigator ------------------------------------------------------------------------------------
class NavigatorLink:
    """The navigator's stream: requests held until it is heard, stops read from its status."""

    def __init__(self, ipc: CarmenIpc) -> None:
        """Read the navigator's stream (its name: ``ipc.streams['navigator']``).

        :param ipc: the program's CARMEN connection.
        """
        self.ipc = ipc
        stream = self.stream = ipc.streams['navigator']
        self.feed = ipc.feed(stream, lambda: Navigator(stream), '_stops', True)
        self.nav: Any = self.feed.obj
        self.watch = StopWatch()
        self.stops = ipc.derived.setdefault(STOPPED, collections.deque())
        self.feed.watchers.append(lambda statuses: self.stops.extend(self.watch.take(statuses)))
        self.held = False
        ipc.collectors.append(self.update)

    def send(self) -> int:
        """Send the request members set, now or once the navigator's reader is matched.

    :returns: 0, as CARMEN's navigator calls do.
    """
        self.held = True
        self.update()
        return 0

    def update(self) -> None:
        """Send held requests once the navigator's reader is matched and a status has come: a
        request written while only our side has matched is lost (discovery runs both ways, not
        at once), and the navigator's status says its side has found us."""
        if self.held and self.nav.peers('request') and self.feed.latest is not None:
            self.held = not self.nav.publish_request()


def _link() -> NavigatorLink:
    ipc = connection()
    link = ipc.links.get('navigator')
    if link is None:
        link = ipc.links['navigator'] = NavigatorLink(ipc)
    return link


def carmen_navigator_set_goal(x: float, y: float) -> int:
    """4.2.1: the one goal (m, map frame).

    :param x: the goal's x (m, map frame).
    :param y: the goal's y (m, map frame).
    :returns: 0 (sent, or held until the navigator is heard).
    :raises InvalidValueError: a value that is not finite.
    """
    if not (math.isfinite(x) and math.isfinite(y)):
        raise InvalidValueError(f'carmen_navigator_set_goal({x}, {y}): finite metres')
    link = _link()
    link.nav.requests.goal.set_value(Point(float(x), float(y)))
    return link.send()


def carmen_navigator_set_goal_place(name: str) -> int:
    """4.2.1: the goal at the map's place ``name`` (no effect if the map has none).

    :param name: a place of the navigator's map.
    :returns: 0 (sent, or held until the navigator is heard).
    """
    link = _link()
    link.nav.requests.goal_place.set_value(str(name))
    return link.send()


def carmen_navigator_go() -> int:
    """4.3: autonomous motion to the goal."""
    link = _link()
    link.nav.requests.autonomous.set_value(True)
    return link.send()


def carmen_navigator_stop() -> int:
    """4.3: leave autonomous motion; answered by autonomous_stopped with USER_STOPPED."""
    link = _link()
    link.nav.requests.autonomous.set_value(False)
    link.watch.stop_sent(link.ipc.manager.now().get_seconds())
    return link.send()


def _status_subscribe(name: str, message_type: type, fill: Any, msg: Any, handler: Handler | None,
                      how: int) -> Any:
    link = _link()
    how = mode(how)
    return link.ipc.subscribe(name, message_type, link.stream, fill, msg, handler, how)


def carmen_navigator_subscribe_status_message(status: carmen_navigator_status_message | None,
                                              handler: Handler | None, subscribe_how: int) -> Any:
    """The navigator's status: autonomous, goal_set, goal, robot (with the base's velocities).

    :param status: the message to fill on each status (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    ipc = connection()
    ipc.odometry_feed()
    return _status_subscribe('carmen_navigator_status', carmen_navigator_status_message,
                             lambda m, d: convert.navigator_status(m, d, ipc.velocity), status, handler,
                             subscribe_how)


def carmen_navigator_subscribe_plan_message(plan: carmen_navigator_plan_message | None,
                                            handler: Handler | None, subscribe_how: int) -> Any:
    """The navigator's plan (ours is empty: the motionModule's plan is not on its interface).

    :param plan: the message to fill on each status (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    return _status_subscribe('carmen_navigator_plan', carmen_navigator_plan_message, convert.navigator_plan,
                             plan, handler, subscribe_how)


def _stopped(msg: Any, d: Any) -> None:
    msg.reason = convert.REASONS.get(int(d.stop_reason), convert.REASONS[3])
    convert.stamp_and_host(msg, d)


def carmen_navigator_subscribe_autonomous_stopped_message(
        autonomous_stopped: carmen_navigator_autonomous_stopped_message | None, handler: Handler | None,
        subscribe_how: int) -> Any:
    """4.3: each end of autonomous motion, with its reason.

    :param autonomous_stopped: the message to fill on each stop (None: the library's own).
    :param handler: called with the message after each fill (None: the message is only updated).
    :param subscribe_how: CARMEN_SUBSCRIBE_LATEST, CARMEN_SUBSCRIBE_ALL or CARMEN_UNSUBSCRIBE.
    :returns: the message filled (None when unsubscribing).
    """
    link = _link()
    return link.ipc.subscribe(STOPPED, carmen_navigator_autonomous_stopped_message, STOPPED, _stopped,
                              autonomous_stopped, handler, subscribe_how)


def _query_status(fill: Any, message_type: type) -> Any:
    link = _link()
    if not link.ipc.wait_for(lambda: link.feed.latest is not None, QUERY_WAIT_S):
        return None
    msg = message_type()
    fill(msg, link.feed.latest)
    return msg


def carmen_navigator_query_status() -> carmen_navigator_status_message | None:
    """3.0.2: the navigator's newest status as a new message (None: none within QUERY_WAIT_S)."""
    ipc = connection()
    ipc.odometry_feed()
    return _query_status(lambda m, d: convert.navigator_status(m, d, ipc.velocity),
                         carmen_navigator_status_message)


def carmen_navigator_query_plan() -> carmen_navigator_plan_message | None:
    """3.0.2: the navigator's plan as a new message (None: no status within QUERY_WAIT_S)."""
    return _query_status(convert.navigator_plan, carmen_navigator_plan_message)


def carmen_navigator_get_map(map_type: int) -> carmen_navigator_map_message | None:
    """5.4: the navigator's map of ``map_type`` as a new message; only CARMEN_NAVIGATOR_MAP_v (the
    map server's grid) exists here: None, with a warning, for the others or without an answer.

    :param map_type: a carmen_navigator_map_t.
    :raises InvalidValueError: a value that is not a carmen_navigator_map_t.
    """
    try:
        kind = carmen_navigator_map_t(map_type)
    except ValueError:
        raise InvalidValueError(f'carmen_navigator_get_map({map_type!r}): a carmen_navigator_map_t') from None
    if kind != CARMEN_NAVIGATOR_MAP_v:
        warn(f'carmen_navigator_get_map: no {kind.name} here; only CARMEN_NAVIGATOR_MAP_v (the map server\'s grid)')
        return None
    ipc = connection()
    stream = ipc.streams['map_server']
    feed = ipc.feed(stream, lambda: MapServer(stream), '_map', False)
    if not ipc.wait_for(lambda: feed.obj.received('info') > 0, QUERY_WAIT_S):
        warn(f'carmen_navigator_get_map: no map from the map server ({stream}) within {QUERY_WAIT_S:.0f} s')
        return None
    msg = carmen_navigator_map_message(map_type=kind)
    convert.navigator_map(msg, feed.obj.info)
    return msg
