"""Pluto's xmlServer: the robot's variables on a TCP socket in Mobotware's "AU Robot Servers" line
protocol (``<var odoPose.pose=""/>`` answered by ``<var name="odoPose.pose" typ="pose" .../>``).

The protocol core is pure Python: :class:`XmlServer` serves a :class:`VariablePool` turn by turn
(:class:`ServerSettings` say how), :class:`XmlClient` talks to it; :mod:`.command` parses command
lines and formats replies.  What fills the pool from the WURDE streams and the node's ``main`` live
in :mod:`.robot_table` and :mod:`.module`.
"""

from .client import XmlClient
from .command import Command, CommandError
from .server import XmlServer
from .session import Session
from .settings import ServerSettings, ServerStats
from .variables import Variable, VariablePool, VarError

__all__ = ['Command', 'CommandError', 'ServerSettings', 'ServerStats', 'Session', 'VarError',
           'Variable', 'VariablePool', 'XmlClient', 'XmlServer']
