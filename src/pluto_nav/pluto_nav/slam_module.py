"""slam_module: Pluto's slamModule (Pluto 7.2) — builds a map of line walls while it improves the
localModule's poses.

"The slam module uses a compressed Kalman Filter to create a map while also using the map to
improve the pose estimates.  Aside from saving the map not doing odometry calibration it works like
the pose module.  The slam thread does not start automatically when you run the slamModule script,
one must start it when ready."  The cycle, the thread and the setter are
:class:`pluto_nav.estimator.Estimator`'s, with a method of :mod:`pluto_nav.slam_methods` (``-e
lines``: :class:`pluto_nav.slam_filter.SlamFilter`; ``-e scans``: graph SLAM for real robots'
data); the setter is 2 while estimating and 3 while saving.  Each start of the thread starts a new
map whose frame is the Laser_Pose (4) the thread started at, taken as exact: the map is drawn in
the frame the localModule's poses are in.

Stopping the thread saves the map ("when the slam thread is stopped the map is saved so one should
wait"), and so does the module's end while the thread runs, which is why it asks the MCP for
:data:`QUIT_TIME_S` after Quit.  The map is saved in the simulator's map format
(:mod:`wurde_idl.mapfile`) with the place ``start``, so a poseModule can load it next run; a method
that builds an occupancy grid also writes a map_server pair beside it (:mod:`wurde_idl.gridmap`).
docs/navigation.md ("Navigation") gives ``slam/status`` and the options; docs/pluto-nav.md ("slamModule")
what it adds.
"""

from __future__ import annotations

import dataclasses
import pathlib
import sys

import numpy as np

from wurde_core import CommsManager, Logger
from wurde_core.module_loop import exit_on_config_error, run_loop, set_loop
from wurde_idl.errors import ConfigError
from wurde_idl.gridmap import save_grid_map
from wurde_idl.mapfile import save_map_data

from .estimator import LOOP_S, Estimator
from .slam_methods import METHODS, SlamMethod
from .streams import SLAM_SAVING, SLAM_SETTER, LocPose

__all__ = ['SlamModule', 'main']

STATUS = 'slam/status'
#: The time the module asks the MCP for between Quit and its signals: the map is saved at the end
#: ("one should wait", Pluto 7.2), and a long run's grid takes seconds to trace on a loaded machine.
QUIT_TIME_S = 60.0
HELP = ('  -f FILE   where to save the map (default slam-map.xml; relative: in the data directory)\n'
        '  -s LASER  the laser module (default PlutoLaser)\n'
        '  -a        start the thread at launch\n'
        '  -e METHOD lines (default: line landmarks, Pluto 7.2) or scans (scan matching, real data)')


class SlamModule(Estimator):
    """The slamModule: a SLAM method; ``element[1] = 2`` saves the map."""

    SETTER = SLAM_SETTER

    def __init__(self, manager: CommsManager, logger: Logger, output: pathlib.Path, *, laser: str,
                 start_running: bool, method: str = 'lines') -> None:
        self.output = output
        self.method_name = method
        self.last: LocPose | None = None
        self.saves = 0
        self.mapped = False                # the current map has had a scan
        super().__init__(manager, logger, METHODS[method](), status=STATUS, laser=laser,
                         start_running=start_running)
        self.data = [0.0, 0.0, 0.0]

    @property
    def slam(self) -> SlamMethod:
        return self.cycle.method  # type: ignore[return-value]

    def _start(self) -> None:
        super()._start()
        if self.running:                   # a new map, its frame set by the first scan
            self.cycle.method = METHODS[self.method_name]()
            self.last, self.mapped = None, False

    def start_covariance(self, adjusted: LocPose) -> np.ndarray:
        """Zero: the map's frame *is* the Laser_Pose the thread started at."""
        return np.zeros((3, 3))

    def estimate(self, dr: LocPose, stamp: float, setter: int) -> LocPose:
        self.mapped = True
        self.data = [*self.slam.status(), float(self.saves)]
        self.last = super().estimate(dr, stamp, setter)
        return self.last

    def command(self) -> None:
        """``element[1] = 2``: save the map now."""
        self.save(resume=True)

    def on_stop(self) -> None:
        self.save(resume=False)

    def close(self) -> None:
        """The module ends: a running thread's map is saved, as a stop would."""
        if self.running:
            self.save(resume=False)

    def save(self, *, resume: bool) -> None:
        """Setter 3 while saving (Pluto 7.2), the file written, element[1] back to 0; ``resume``:
        the estimate cycle goes on (setter 2 again)."""
        self.element[1] = -1
        self.publish_status()
        holding = self.running and self.last is not None
        if holding:
            assert self.last is not None
            self.write_post(dataclasses.replace(self.last, setter=SLAM_SAVING))
        if self.mapped:
            self._write_map()
        else:
            self.logger.warning(f'{self.manager.name}: nothing mapped yet; {self.output} left as it is')
        if holding and resume:
            assert self.last is not None
            self.write_post(self.last)
        self.element[1] = 0
        self.data = [*self.slam.status(), float(self.saves)]
        self.publish_status()

    def _write_map(self) -> None:
        data = self.slam.map_data(f'slam-{self.manager.name}', mount=self._mount())
        grid = self.slam.grid()
        try:
            self.output.parent.mkdir(parents=True, exist_ok=True)
            save_map_data(data, self.output)
            if grid is not None:
                save_grid_map(self.output.with_suffix('.yaml'), grid.cells, origin=grid.origin,
                              resolution=grid.resolution)
        except (OSError, ConfigError, ValueError) as error:
            self.logger.error(f'{self.manager.name}: could not save the map to {self.output}: {error}')
            return
        self.saves += 1
        beside = f' and {self.output.with_suffix(".yaml").name}' if grid is not None else ''
        self.logger.notice(f'{self.manager.name}: map saved to {self.output}{beside} ({len(data.walls)} walls)')

    def _mount(self) -> np.ndarray:
        """The laser's mounting on the robot (its RangeFinder info): the map's start is a robot pose."""
        info = self.scan.info
        return np.array([float(info.x_offset.get_value()), float(info.y_offset.get_value()), 0.0])


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('slamModule')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'f:s:ae:').user
    output = pathlib.Path(manager.config.get_data_directory()) / opts.get('f', 'slam-map.xml')
    method = opts.get('e', 'lines')
    if method not in METHODS:
        return exit_on_config_error(argv[0], ConfigError(argv[0], None, f'-e {method}: the methods are '
                                                                      f'{", ".join(METHODS)}'))
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = SlamModule(manager, logger, output, laser=opts.get('s', 'PlutoLaser'), start_running='a' in opts,
                        method=method)
    set_loop(manager, LOOP_S)
    manager.set_quit_time(QUIT_TIME_S)
    when = 'now' if 'a' in opts else 'when asked (slam/status element[0] = 1)'
    logger.notice(f'{manager.name}: method {method}; the map goes to {output}; the thread starts {when}')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
