"""CARMEN's robot-program API on our streams, so that a CARMEN program ports line by line
(Programming with CARMEN 3–5)::

    from pluto_motion.carmen import *

    def odometry_handler(odometry):
        print(odometry.x, odometry.y, odometry.theta, odometry.tv)

    carmen_ipc_initialize(sys.argv)
    carmen_base_subscribe_odometry_message(None, odometry_handler, CARMEN_SUBSCRIBE_LATEST)
    carmen_navigator_set_goal_place('office2')
    carmen_navigator_go()
    carmen_ipc_dispatch()

Underneath are WURDE consumers of the program's CommsManager (:mod:`.ipc`), so the program runs
under the MCP or alone (``ros2 run``, ``python3 prog.py``) and takes WURDE's options (``-n``).
"""

from .connection import (STREAMS, carmen_ipc_addPeriodicTimer, carmen_ipc_disconnect, carmen_ipc_dispatch,
                         carmen_ipc_initialize, carmen_ipc_sleep)
from .messages import (CARMEN_INITIALIZE_GAUSSIAN, CARMEN_INITIALIZE_UNIFORM, CARMEN_LOCALIZE_GMAP_v,
                       CARMEN_LOCALIZE_LMAP_v, CARMEN_NAVIGATOR_COST_v, CARMEN_NAVIGATOR_ENTROPY_v,
                       CARMEN_NAVIGATOR_GOAL_REACHED_v, CARMEN_NAVIGATOR_MAP_v, CARMEN_NAVIGATOR_UNKNOWN_v,
                       CARMEN_NAVIGATOR_USER_STOPPED_v, CARMEN_NAVIGATOR_UTILITY_v, CARMEN_SUBSCRIBE_ALL,
                       CARMEN_SUBSCRIBE_LATEST, CARMEN_UNSUBSCRIBE, carmen_base_bumper_message,
                       carmen_base_ir_message, carmen_base_odometry_message, carmen_base_sonar_message,
                       carmen_laser_laser_message, carmen_localize_globalpos_message,
                       carmen_localize_particle_message, carmen_map_config_t,
                       carmen_navigator_autonomous_stopped_message, carmen_navigator_map_message,
                       carmen_navigator_map_t, carmen_navigator_plan_message, carmen_navigator_reason_t,
                       carmen_navigator_status_message, carmen_point_t, carmen_robot_laser_message,
                       carmen_subscribe_t, carmen_traj_point_t)
from .navigation import (carmen_localize_initialize_gaussian_command, carmen_localize_initialize_uniform_command,
                         carmen_localize_query_globalpos, carmen_localize_query_particles,
                         carmen_localize_subscribe_globalpos_message, carmen_navigator_get_map,
                         carmen_navigator_go, carmen_navigator_query_plan, carmen_navigator_query_status,
                         carmen_navigator_set_goal, carmen_navigator_set_goal_place, carmen_navigator_stop,
                         carmen_navigator_subscribe_autonomous_stopped_message,
                         carmen_navigator_subscribe_plan_message, carmen_navigator_subscribe_status_message)
from .robot import (carmen_robot_subscribe_frontlaser_message, carmen_robot_subscribe_rearlaser_message,
                    carmen_robot_velocity_command)
from .sensors import (carmen_base_subscribe_bumper_message, carmen_base_subscribe_ir_message,
                      carmen_base_subscribe_odometry_message, carmen_base_subscribe_sonar_message,
                      carmen_laser_subscribe_frontlaser_message, carmen_laser_subscribe_rearlaser_message)

__all__ = [
    'CARMEN_INITIALIZE_GAUSSIAN', 'CARMEN_INITIALIZE_UNIFORM', 'CARMEN_LOCALIZE_GMAP_v', 'CARMEN_LOCALIZE_LMAP_v',
    'CARMEN_NAVIGATOR_COST_v', 'CARMEN_NAVIGATOR_ENTROPY_v', 'CARMEN_NAVIGATOR_GOAL_REACHED_v',
    'CARMEN_NAVIGATOR_MAP_v', 'CARMEN_NAVIGATOR_UNKNOWN_v', 'CARMEN_NAVIGATOR_USER_STOPPED_v',
    'CARMEN_NAVIGATOR_UTILITY_v', 'CARMEN_SUBSCRIBE_ALL', 'CARMEN_SUBSCRIBE_LATEST', 'CARMEN_UNSUBSCRIBE',
    'STREAMS', 'carmen_base_bumper_message', 'carmen_base_ir_message', 'carmen_base_odometry_message',
    'carmen_base_sonar_message', 'carmen_base_subscribe_bumper_message', 'carmen_base_subscribe_ir_message',
    'carmen_base_subscribe_odometry_message', 'carmen_base_subscribe_sonar_message',
    'carmen_ipc_addPeriodicTimer', 'carmen_ipc_disconnect', 'carmen_ipc_dispatch', 'carmen_ipc_initialize',
    'carmen_ipc_sleep', 'carmen_laser_laser_message', 'carmen_laser_subscribe_frontlaser_message',
    'carmen_laser_subscribe_rearlaser_message', 'carmen_localize_globalpos_message',
    'carmen_localize_initialize_gaussian_command', 'carmen_localize_initialize_uniform_command',
    'carmen_localize_particle_message', 'carmen_localize_query_globalpos', 'carmen_localize_query_particles',
    'carmen_localize_subscribe_globalpos_message', 'carmen_map_config_t',
    'carmen_navigator_autonomous_stopped_message', 'carmen_navigator_get_map', 'carmen_navigator_go',
    'carmen_navigator_map_message', 'carmen_navigator_map_t', 'carmen_navigator_plan_message',
    'carmen_navigator_query_plan', 'carmen_navigator_query_status', 'carmen_navigator_reason_t',
    'carmen_navigator_set_goal', 'carmen_navigator_set_goal_place', 'carmen_navigator_status_message',
    'carmen_navigator_stop', 'carmen_navigator_subscribe_autonomous_stopped_message',
    'carmen_navigator_subscribe_plan_message', 'carmen_navigator_subscribe_status_message', 'carmen_point_t',
    'carmen_robot_laser_message', 'carmen_robot_subscribe_frontlaser_message',
    'carmen_robot_subscribe_rearlaser_message', 'carmen_robot_velocity_command', 'carmen_subscribe_t',
    'carmen_traj_point_t',
]
