"""The logging system (guide chapter 4): stderr, syslog local0, ROS /rosout, and the network.

``Logger("FooServer")`` is a supplier of the LoggerTransport interface (stream ``log/FooServer``):
register it with ``manager.register_supplier(logger)`` and every message also goes out over the
network, where any consumer of that stream reads it.  Messages below the configured level
(role-config ``<log level>``, ``WURDE_LOG_LEVEL``; default debug) are dropped.  When the
configuration names a log directory, messages are also appended to ``<directory>/<name>.log``.
The first Logger becomes the global one used by :func:`g_debug` ... :func:`g_fatal`; without one,
those write to stderr.
"""

from __future__ import annotations

import socket
import sys
import syslog
import time
from typing import Any, TextIO

from . import module_context
from .errors import InvalidValueError
from .robot_object import RobotObject
from .role_config import LOG_LEVELS, global_configuration

DEBUG, INFO, NOTICE, WARN, ERROR, FATAL = range(6)
_SYSLOG_PRIORITY = (syslog.LOG_DEBUG, syslog.LOG_INFO, syslog.LOG_NOTICE, syslog.LOG_WARNING,
                    syslog.LOG_ERR, syslog.LOG_CRIT)
STREAM_PREFIX = 'log/'

_global: 'ModuleLogger | None' = None


def _level_number(level: int | str) -> int:
    if isinstance(level, str):
        if level not in LOG_LEVELS:
            raise InvalidValueError(f'log level {level!r} is not one of {", ".join(LOG_LEVELS)}')
        return LOG_LEVELS.index(level)
    if not 0 <= level < len(LOG_LEVELS):
        raise InvalidValueError(f'log level {level} is not 0..{len(LOG_LEVELS) - 1}')
    return int(level)


class ModuleLogger(RobotObject, interface='LoggerTransport'):
    """A named logger; also a LoggerTransport supplier once registered."""

    def __init__(self, name: str, *, stderr: bool = True, use_syslog: bool = True) -> None:
        """A logger whose network stream is ``log/<name>``; the first one made in the process
        becomes the global logger.

        :param name: the logger's name: the label of each line, the syslog ident and the log
            file's name (``<name>.log``).
        :param stderr: write each message to stderr as ``[LEVEL] name: text``.
        :param use_syslog: send each message to syslog (facility local0).
        """
        super().__init__(STREAM_PREFIX + name)
        self.name = name
        self._stderr: TextIO | None = sys.stderr if stderr else None
        self._syslog = use_syslog
        self._file: TextIO | None = None
        self._file_dir: str | None = None
        self._host = socket.gethostname()
        self.set_queue_mode(True)
        if use_syslog:
            syslog.openlog(name, syslog.LOG_PID, syslog.LOG_LOCAL0)
        global _global
        if module_context.current() is not None:      # a contained module's own (issue 39)
            if module_context.singleton('logger', None) is None:
                module_context.set_singleton('logger', self)
        elif _global is None:
            _global = self

    def level(self) -> int:
        """Lowest level logged, from the global configuration."""
        return LOG_LEVELS.index(global_configuration().get_log_level())

    def log(self, level: int | str, message: str) -> bool:
        """Log ``message`` at ``level`` on every output: stderr, syslog, the log file (when the
        configuration names a log directory), the node's ``/rosout`` once registered, and the
        network once registered as a supplier.

        :param level: 0 (debug) .. 5 (fatal), or a level name (``"warn"``).
        :param message: the text; a trailing newline is dropped.
        :returns: whether it passed the level filter (the configured log level).
        :raises InvalidValueError: for an unknown level.
        """
        number = _level_number(level)
        if number < self.level():
            return False
        text = str(message).rstrip('\n')
        label = LOG_LEVELS[number].upper()
        if self._stderr is not None:
            print(f'[{label}] {self.name}: {text}', file=self._stderr, flush=True)
        if self._syslog:
            syslog.syslog(_SYSLOG_PRIORITY[number], text)
        self._to_file(label, text)
        self._to_ros(number, text)
        self._to_network(number, text)
        return True

    def _to_file(self, label: str, text: str) -> None:
        config = global_configuration()
        directory = config.get_log_directory() if config.explicit_log_directory() else None
        if directory != self._file_dir:
            if self._file is not None:
                self._file.close()
            self._file = open(f'{directory}/{self.name}.log', 'a') if directory else None  # noqa: SIM115
            self._file_dir = directory
        if self._file is not None:
            stamp = time.strftime('%Y-%m-%d %H:%M:%S')
            self._file.write(f'{stamp} [{label}] {text}\n')
            self._file.flush()

    def _to_ros(self, number: int, text: str) -> None:
        manager = self._manager
        if manager is None or manager.node is None:
            return
        ros_logger = manager.node.get_logger()
        # rclpy binds a severity to each call site ("Logger severity cannot be changed between
        # calls"), so every severity needs a line of its own.
        if number == 0:
            ros_logger.debug(text)
        elif number in (1, 2):
            ros_logger.info(text)
        elif number == 3:
            ros_logger.warning(text)
        elif number == 4:
            ros_logger.error(text)
        else:
            ros_logger.fatal(text)

    def _to_network(self, number: int, text: str) -> None:
        if self.role != 'supplier' or not self.is_connected():
            return
        self.data.level = number
        self.data.message = text
        self.data.host = self._host
        self.publish_data()

    def debug(self, message: str) -> bool:
        """Log at debug level.

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(DEBUG, message)

    def info_msg(self, message: str) -> bool:
        """Log at info level (``info`` is the interface's info channel).

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(INFO, message)

    def notice(self, message: str) -> bool:
        """Log at notice level.

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(NOTICE, message)

    def warn(self, message: str) -> bool:
        """Log at warn level (also named ``warning``).

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(WARN, message)

    warning = warn

    def error(self, message: str) -> bool:
        """Log at error level.

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(ERROR, message)

    def fatal(self, message: str) -> bool:
        """Log at fatal level (the program goes on: ending it is the caller's choice).

        :param message: the text.
        :returns: whether it passed the level filter.
        """
        return self.log(FATAL, message)

    def close(self) -> None:
        """Close the log file, if any; idempotent."""
        if self._file is not None:
            self._file.close()
            self._file = None
            self._file_dir = None


# The guide's name (3.4.10, chapter 4), kept as an alias of the canonical one (docs/naming.md).
Logger = ModuleLogger


def global_logger() -> ModuleLogger | None:
    """The first Logger created in this process (in a container: by this module), if any."""
    return module_context.singleton('logger', _global)


def _global_log(level: int, message: Any) -> None:
    logger = global_logger()
    if logger is not None:
        logger.log(level, str(message))
    else:
        print(f'[{LOG_LEVELS[level].upper()}] {message}', file=sys.stderr, flush=True)


def g_debug(message: Any) -> None:
    """Log at debug level through the global logger, or to stderr when there is none.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(DEBUG, message)


def g_info(message: Any) -> None:
    """Log at info level through the global logger, or to stderr.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(INFO, message)


def g_notice(message: Any) -> None:
    """Log at notice level through the global logger, or to stderr.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(NOTICE, message)


def g_warn(message: Any) -> None:
    """Log at warn level through the global logger, or to stderr.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(WARN, message)


def g_error(message: Any) -> None:
    """Log at error level through the global logger, or to stderr.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(ERROR, message)


def g_fatal(message: Any) -> None:
    """Log at fatal level through the global logger, or to stderr.

    :param message: the text (anything: ``str()`` of it).
    """
    _global_log(FATAL, message)
