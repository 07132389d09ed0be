"""wurde_idl: WURDE interface definition files for ROS 2.

Reads interface XML in the syntax of the WURDE Programming Guide (chapter 3), refuses anything else
with file, line and reason, and generates ROS 2 ``.msg`` files plus a run-time description of each
interface.  Also home of what every package of the suite shares without importing each other: the
root exception, the one hardened XML reader (with checked element and attribute access) and the
map file format (:mod:`wurde_idl.mapfile`).
"""

from .description import load, load_all
from .errors import ConfigError, InterfaceError, MapError, UnknownInterfaceError, WurdeError
from .mapfile import MapData, load_map_data, save_map_data
from .model import Interface, Member, StructType
from .msg_writer import messages
from .reader import read_interface, read_interfaces
from .safe_xml import parse_bytes, parse_file

__all__ = [
    'ConfigError', 'Interface', 'InterfaceError', 'MapData', 'MapError', 'Member', 'StructType',
    'UnknownInterfaceError', 'WurdeError', 'load', 'load_all', 'load_map_data', 'messages',
    'parse_bytes', 'parse_file', 'read_interface', 'read_interfaces', 'save_map_data',
]
