"""pose_i: Pluto's keyboard program for the poseModule (Pluto 7.1), one command per line on stdin.

====================== ==========================================================================
command                what
====================== ==========================================================================
``pose``               print Localization/Pose (3): x y theta, its setter and standard deviations
``stop`` / ``start``   stop or start the poseModule's thread (``pose/status`` element[0])
``set X Y THETA``      set the robot's pose, as Pluto 7.1 says: stop the pose thread and wait until
                       the setter is 0, write the robot pose with setter -1 and wait until the
                       localization shows it, start the thread again and wait for setter 1
``wall``               find the longest wall in front: element[1] = 2, wait for the answer, print
                       the number of points, gamma, rho (laser frame) and their standard deviations
``calibrate [D A]``     calibrate the odometry against the wall in front (Pluto 7.1): back away
                       ``D`` m (1), turn ``A`` rad (0.5) and back, through the driveModule; the
                       find-wall's distances and angles against the odometry's give the new
                       scales, written to the calibration file (:mod:`.calibration_run`,
                       :mod:`.odometry_calibration`) for the driveModule's next start
``quit``               end
====================== ==========================================================================

Each command prints one line beginning ``ok`` or ``error``; waits give up after ``-t SECONDS``
(default 10).  ``-b BASE`` (PlutoBase) is the base whose odometry ``calibrate`` reads, ``-k FILE``
the calibration file it writes (default ``odometry-calibration.yaml`` in the config directory).
"""

from __future__ import annotations

import math
import select
import sys
import time
from collections.abc import Callable

from wurde_core import CommsManager, RunState
from wurde_core.interfaces import FVectorState
from wurde_core.module_loop import config_file

from .calibration_run import CalibrationRun
from .loc_proxy import LocProxy
from .odometry_calibration import DEFAULT_FILE, write_calibration
from .streams import NOBODY, POSE, POSE_SETTER, USER_SETTER

__all__ = ['main']

STATUS = 'pose/status'


class PoseInterface:
    """The poseModule's status stream and the localization, for the commands."""

    def __init__(self, manager: CommsManager, timeout: float) -> None:
        self.manager = manager
        self.timeout = timeout
        self.loc = LocProxy(manager, 1 << POSE)
        self.status = FVectorState(STATUS)
        self.status.set_queue_mode(True)      # every status in order: the find-wall's -1 too
        manager.register_consumer(self.status)
        self.element: list[int] = []
        self.data: list[float] = []
        self.searching = False                # a find-wall's -1 seen, its answer not yet

    def _take_status(self) -> None:
        while self.status.get_next_data():
            self.element = list(self.status.data.element)
            self.data = list(self.status.data.data)
            if len(self.element) > 1 and self.element[1] == -1:
                self.searching = True

    def _until(self, test: object) -> bool:
        deadline = time.monotonic() + self.timeout
        while True:
            self._take_status()
            if test():  # type: ignore[operator]
                return True
            if time.monotonic() >= deadline or self.manager.run_update() != RunState.RUN:
                return False

    def _request(self, element: list[int]) -> bool:
        """Write a status request once the poseModule reads them: a request sent before the
        stream is matched (discovery takes seconds on a loaded machine) would be lost."""
        if not self._until(lambda: self.status.peers('request') > 0):
            return False
        self.status.requests.element.set_value(element)
        self.status.publish_request()
        return True

    def _thread(self, run: bool) -> bool:
        if not self._request([1 if run else 0]):
            return False
        return self._until(lambda: len(self.element) > 0 and self.element[0] == (1 if run else 0))

    def pose(self) -> str:
        if not self._until(lambda: self.loc.get_pose(POSE) is not None):
            return 'error: no pose from the localization'
        p = self.loc.get_pose(POSE)
        assert p is not None
        c = p.covariance
        return (f'ok pose {p.pose[0]:.3f} {p.pose[1]:.3f} {p.pose[3]:.4f} setter {p.setter} '
                f'sigma {math.sqrt(max(c[0, 0], 0)):.3f} {math.sqrt(max(c[1, 1], 0)):.3f} '
                f'{math.sqrt(max(c[2, 2], 0)):.4f}')

    def stop(self) -> str:
        if not self._thread(False):
            return 'error: the pose thread did not stop'
        if not self.loc.wait_for_setter(lambda s: s <= NOBODY, self.timeout):
            return 'error: the setter was not released'
        return 'ok stopped'

    def start(self) -> str:
        if not self._thread(True):
            return 'error: the pose thread did not start'
        return 'ok started'

    def set(self, x: float, y: float, theta: float) -> str:
        """Pluto 7.1: stop the thread, set the pose with setter -1, start again — waiting between."""
        stopped = self.stop()
        if not stopped.startswith('ok'):
            return stopped
        self.loc.set_pose((x, y, theta), USER_SETTER)
        if not self.loc.wait_for_setter(USER_SETTER, self.timeout):
            return 'error: the localization did not take the pose'
        if not self._thread(True) or not self.loc.wait_for_setter(POSE_SETTER, self.timeout):
            return 'error: the pose thread did not take over'
        return f'ok set {x:.3f} {y:.3f} {theta:.4f}'

    def _find_wall(self) -> str:
        """Run the find-wall: '' once its answer is in element[1] and data, else the error."""
        self._take_status()
        self.searching = False
        if not self._request([self.element[0] if self.element else 1, 2]):
            return 'error: no poseModule reads pose/status requests'
        if not self._until(lambda: self.searching and self.element[1] >= 0):
            return 'error: no answer from the find-wall'
        return ''

    def calibrate(self, run: CalibrationRun, path: str, distance: float = 1.0, angle: float = 0.5) -> str:
        """Measure the odometry against the wall in front and write the calibration file."""
        if not (0.1 <= distance <= 5.0 and 0.1 <= angle <= 0.7):
            return 'error: calibrate D A wants 0.1 <= D <= 5 m and 0.1 <= A <= 0.7 rad'

        def wall() -> tuple[float, float] | str:
            problem = self._find_wall()
            if problem:
                return problem
            if self.element[1] == 0:
                return 'error: no wall in front'
            return self.data[0], self.data[1]

        measured = run.run(wall, distance, angle)
        if isinstance(measured, str):
            return measured if measured.startswith('error') else f'error: {measured}'
        try:
            write_calibration(path, measured.new)
        except (OSError, ValueError) as error:
            return f'error: {path}: {error}'
        m = measured
        return (f'ok calibration distance {m.new.distance:.5f} rotation {m.new.rotation:.5f} '
                f'(was {m.old.distance:.5f} {m.old.rotation:.5f}; wall {m.true_distance:.4f} m '
                f'{m.true_angle:.4f} rad, odometry {m.odometry_distance:.4f} m {m.odometry_angle:.4f} rad) '
                f'written to {path}')

    def wall(self) -> str:
        problem = self._find_wall()
        if problem:
            return problem
        if self.element[1] == 0:
            return 'ok wall none'
        gamma, rho, c00, _, _, c11 = self.data[:6]
        return (f'ok wall {self.element[1]} gamma {gamma:.4f} rho {rho:.3f} '
                f'sigma {math.sqrt(max(c00, 0)):.4f} {math.sqrt(max(c11, 0)):.4f}')


def _command(ui: PoseInterface, line: str, calibrate: Callable[[list[float]], str]) -> str | None:
    words = line.split()
    if not words:
        return ''
    name, args = words[0], words[1:]
    if name == 'quit':
        return None
    try:
        if name == 'set' and len(args) == 3:
            return ui.set(*(float(a) for a in args))
        if name == 'calibrate' and len(args) in (0, 2):
            return calibrate([float(a) for a in args])
        if name in ('pose', 'stop', 'start', 'wall') and not args:
            return getattr(ui, name)()
    except ValueError:
        pass
    return f'error: unknown command {line.strip()!r} (pose, stop, start, set X Y THETA, wall, calibrate [D A], quit)'


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('pose_i')
    manager.set_help_string('  -t SECONDS  how long a command waits for an answer (default 10)\n'
                            '  -b BASE     the base whose odometry calibrate reads (PlutoBase)\n'
                            '  -k FILE     the calibration file calibrate writes (odometry-calibration.yaml)\n'
                            '  commands on stdin: pose, stop, start, set X Y THETA, wall, calibrate [D A], quit')
    opts = manager.parse_options(argv, 't:b:k:').user
    ui = PoseInterface(manager, float(opts.get('t', 10.0)))
    run = CalibrationRun(manager, opts.get('b', 'PlutoBase'), ui.timeout)
    path = config_file(manager, opts.get('k'), DEFAULT_FILE)
    print('pose_i ready', flush=True)
    try:
        while manager.run_update() == RunState.RUN:
            ready, _, _ = select.select([sys.stdin], [], [], 0.0)
            if not ready:
                continue
            line = sys.stdin.readline()
            if not line:
                break
            answer = _command(ui, line, lambda args: ui.calibrate(run, path, *args))
            if answer is None:
                break
            if answer:
                print(answer, flush=True)
    finally:
        manager.clean_up()
    return 0


if __name__ == '__main__':
    sys.exit(main())
