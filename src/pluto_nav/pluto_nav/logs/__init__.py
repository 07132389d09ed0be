"""Real robots' recordings as records: CARMEN logs (:mod:`.carmen`) and rosbag2 bags
(:mod:`.rosbag`), read into the same :mod:`.records`, and a whole recording in memory
(:class:`.robot_log.RobotLog`, :func:`.robot_log.load_log`)."""

from .problems import LogError, LogProblems
from .records import (ImuRecord, LaserConfig, LogRecord, OdometryRecord, ParamRecord, ScanRecord,
                      TruePoseRecord)
from .robot_log import RobotLog, load_log

__all__ = ['ImuRecord', 'LaserConfig', 'LogError', 'LogProblems', 'LogRecord', 'OdometryRecord',
           'ParamRecord', 'RobotLog', 'ScanRecord', 'TruePoseRecord', 'load_log']
