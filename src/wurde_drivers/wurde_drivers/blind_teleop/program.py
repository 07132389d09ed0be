"""blind_teleop (the guide's ``blindTeleop``): drive the robot with a USB joystick (WURDE guide
1.1.5, 7.9).

The guide's program on wurde_core: module ``BlindTeleop`` (``-n`` renames it) consumes
Egomotion (alias ``EgoClient``), ObstacleAvoider (``AvoiderClient``) and PTUnit (``PTUClient``),
all ``ConnectionStrategy.ASSIGNED``, so the MCP's mappings wire them.  Each turn of the loop
(``wurde_core.module_loop.run_loop``) it reads the joystick, asks the avoider to move to a point
ahead, to turn a quarter, or to stop (:mod:`.drive`), sends the PTU's pan and tilt, and handles
the buttons ``resetPTU``, ``stop`` and ``quit``; a status line shows the location and the relative
goal.  Options: ``-j DEVICE`` the joystick (default ``/dev/input/js0``; any path that carries
js_event records, such as the ``joystick_emulator``'s FIFO), ``-c FILE`` its config (default
``joystick-config.xml`` in the config directory), ``-J NAME`` which ``<joystick>`` of it.

Beyond the printed program: a joystick that is absent is reported and retried, and nothing is
commanded until it has told its state; when it vanishes the avoider is told to stop once and
nothing more is commanded until it is back.  Quit (the button) stops the avoider, waits up to a
second for the stop to be delivered, and ends the program with status 0; ended otherwise (the
MCP's Quit, SIGINT) it stops the avoider the same way if it was driving.
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, ConnectionStrategy, Logger, Point, Pose, RunState
from wurde_core.interfaces import Egomotion, ObstacleAvoider, PTUnit
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_idl.errors import ConfigError

from ..joystick.controller import GameController, configure_joystick
from .drive import drive, pan, tilt

__all__ = ['BlindTeleop', 'main']

HELP = """  -j DEVICE  the joystick (default /dev/input/js0; a js_event FIFO such as joystick_emulator's)
  -c FILE    joystick-config.xml (default: <config dir>/joystick-config.xml)
  -J NAME    the <joystick> of the config to use (default: the first)"""
DEFAULT_DEVICE = '/dev/input/js0'
#: The loop's sleep (s): WURDE's default.
LOOP_S = 0.1
#: How long Quit waits for the avoider to acknowledge the stop (s).
STOP_DELIVERY_S = 1.0


class BlindTeleop:
    """The program's state and one turn of its loop (:meth:`step`)."""

    def __init__(self, manager: CommsManager, logger: Logger, joystick: GameController) -> None:
        self.manager = manager
        self.logger = logger
        self.joystick = joystick
        self.ego = Egomotion(ConnectionStrategy.ASSIGNED, 'EgoClient')
        self.avoider = ObstacleAvoider(ConnectionStrategy.ASSIGNED, 'AvoiderClient')
        self.ptu = PTUnit(ConnectionStrategy.ASSIGNED, 'PTUClient')
        for obj in (self.ego, self.avoider, self.ptu):
            manager.register_consumer(obj)
        self.curr = Pose()
        self.goal = Point()
        self.brakeon = True
        self._driving = False    # whether the joystick was there on the last turn
        self._last_status = ''

    def step(self) -> None:
        self.joystick.update()
        if self.ego.new_data():
            self.ego.get_next_data()
            self.curr = self.ego.data.location
        if self.avoider.new_info():
            self.avoider.get_next_info()
            self.brakeon = bool(self.avoider.info.brake.get_value())
        if self.joystick.ready:
            self._driving = True
            self._command()
        elif self._driving:
            self._driving = False
            self.goal = Point()
            self.avoider.stop()
            self.logger.warn(f'{self.manager.name}: the joystick stopped: avoider told to stop')
        self._status()

    def _command(self) -> None:
        """The printed program's lines 50-104."""
        joystick, avoider, ptu = self.joystick, self.avoider, self.ptu
        command = drive(joystick.axis('translate'), joystick.axis('rotate'))
        self.goal = Point(*command.goal)
        if command.verb == 'move':
            avoider.requests.brake.set_value(False)
            avoider.move_to_relative_point(self.goal)
        elif command.verb == 'rotate':
            avoider.requests.brake.set_value(False)
            avoider.rotate_to_relative_angle(command.angle)
        else:
            avoider.stop()
        ptu.requests.tilt.set_value(tilt(joystick.axis('quicktilt')))
        ptu.requests.pan.set_value(pan(joystick.axis('quickpan')))
        ptu.publish_request()
        if joystick.button('resetPTU'):
            ptu.requests.pan.set_value(0.0)
            ptu.requests.tilt.set_value(0.0)
            ptu.publish_request()
        if joystick.button('stop'):
            avoider.stop()
        if joystick.button('quit'):
            avoider.stop()
            avoider.wait_delivered(STOP_DELIVERY_S)
            self.logger.notice(f'{self.manager.name}: quit button')
            self.manager.set_state(RunState.QUIT)

    def _status(self) -> None:
        """The guide's status line, rewritten in place; only when it changed (under the MCP it
        goes to the module's log)."""
        c, g = self.curr, self.goal
        line = (f'\015Location: ({c.x():f},{c.y():f},{c.theta():f})\t\tRelative Goal: '
                f'({g.x():f},{g.y():f})')
        if line != self._last_status:
            self._last_status = line
            print(line, end='', flush=True)

    def close(self) -> None:
        """Leave the robot stopped if this program was driving it, however the program ends
        (quit button, the MCP's Quit, SIGINT): the stop is the module's last word, sent although
        the module is quitting (``set_mcp_traffic``), and waited for up to a second."""
        try:
            if self._driving:
                self.avoider.set_mcp_traffic(True)
                sent = self.avoider.stop() and self.avoider.wait_delivered(STOP_DELIVERY_S)
                self.logger.notice(f'{self.manager.name}: quitting: avoider told to stop'
                                   f'{"" if sent else " (not acknowledged)"}')
        finally:
            self.joystick.close()
            print(flush=True)        # end the status line


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('BlindTeleop')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'j:c:J:').user
    logger = Logger(manager.name)
    joystick = GameController(report=logger.notice)
    try:
        configure_joystick(config_file(manager, user.get('c'), 'joystick-config.xml'), joystick,
                           user.get('J'))
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    manager.register_supplier(logger)
    program = BlindTeleop(manager, logger, joystick)
    joystick.open(user.get('j', DEFAULT_DEVICE))
    set_loop(manager, LOOP_S)   # the guide's 0.1 s sleep; a 1 s heartbeat TTL, as every module
    return run_loop(manager, program.step, program.close)


if __name__ == '__main__':
    sys.exit(main())
