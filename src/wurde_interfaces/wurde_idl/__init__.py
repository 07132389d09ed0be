"""wurde_idl: WURDE interface definition files for ROS 2.

Reads interface XML in the syntax of the WURDE Programming Guide (chapter 3), refuses anything else
with file, line and reason, and generates ROS 2 ``.msg`` files plus a run-time description of each
interface.  Also home of the suite's root exception and its one hardened XML reader.
"""

from .description import load, load_all
from .errors import ConfigError, InterfaceError, UnknownInterfaceError, WurdeError
from .model import Interface, Member, StructType
from .msg_writer import messages
from .reader import read_interface, read_interfaces
from .safe_xml import parse_bytes, parse_file

__all__ = [
    'ConfigError', 'Interface', 'InterfaceError', 'Member', 'StructType', 'UnknownInterfaceError',
    'WurdeError', 'load', 'load_all', 'messages', 'parse_bytes', 'parse_file', 'read_interface',
    'read_interfaces',
]
