"""pose_module: Pluto's poseModule (Pluto 7.1) — laser lines matched to an a-priori map in a
Kalman filter, improving the localModule's poses.

It "uses a priori map and the laser scanner to improve the dead-reckoning of the localization
module.  It first extracts features from the laser scan then matches them to the map.  It then
feeds this along with the dead-reckoning pose into a Kalman Filter to get an improved pose which it
writes to the localization module."  The cycle, the thread and the setter are
:class:`pluto_nav.estimator.Estimator`'s: the filter is :class:`pluto_nav.pose_filter.PoseFilter`
(lines matched to the map's walls with a statistical gate; ``-e scans``: every laser point matched
to the map, :mod:`pluto_nav.localizers` says which suits what), the setter is 1, and the thread
runs from the start unless ``-x``.

``pose/status`` (FVectorState, Pluto 7.1; elements 2 and 3 are ours) and the options are in the
docs/navigation.md ("Navigation"); docs/pluto-nav.md ("poseModule") adds the status layout's detail and the
tunables: the matcher's gates and ranges are ROS 2 parameters (:data:`MATCH_TUNABLES`,
``match.<field>`` of :class:`pluto_nav.matching.MatchSettings`), taken at the next scan.
"""

from __future__ import annotations

import sys

import numpy as np

from wurde_core import CommsManager, Logger
from wurde_core.module_loop import config_file, exit_on_config_error, run_loop, set_loop
from wurde_core.parameters import TunedSettings
from wurde_idl.errors import ConfigError
from wurde_idl.maps import load_map

from .estimation import Method, Scan
from .estimator import LOOP_S, Estimator
from .find_wall import find_wall
from .localizers import LineLocalizer, ScanLocalizer, wall_points
from .pose_filter import PoseFilter
from .relocalize import Relocalization
from .streams import POSE_SETTER
from .wall_map import WallMap

__all__ = ['PoseModule', 'main']

STATUS = 'pose/status'
HELP = ('  -m MAP    the a-priori map (default map.xml in the config directory)\n'
        '  -s LASER  the laser module (default PlutoLaser)\n'
        '  -x        do not start the thread at launch\n'
        '  -e METHOD lines (default: line features, Pluto 7.1) or scans (every laser point)')
METHODS = ('lines', 'scans')
#: The matcher's settings a user may tune while it runs (``match.<field>``).
MATCH_TUNABLES = {
    'gate_probability': ('probability mass of the chi-square gate matching a line to a wall', 0.5, 0.999999),
    'fallback_gate_probability': ('the wider gate, for lines that fit no wall within the first', 0.5, 0.9999999),
    'max_range': ('m: walls beyond this are not expected in a scan', 0.1, 100.0),
    'overlap_tolerance': ('m of slack at the ends of a wall for the overlap test', 0.0, 2.0),
    'min_coverage': ('fraction of an observed segment that must lie on the wall', 0.0, 1.0),
    'ambiguity_margin': ('squared-distance lead the best wall needs over a second one', 0.0, 100.0)}


class PoseModule(Estimator):
    """The poseModule: a localizer against an a-priori map; ``element[1] = 2`` is the find-wall."""

    SETTER = POSE_SETTER

    def __init__(self, manager: CommsManager, logger: Logger, wall_map: WallMap, *, laser: str,
                 start_running: bool, method: str = 'lines') -> None:
        self.wall_map = wall_map
        self.find_wall_pending = False
        self.tuned = TunedSettings(manager, PoseFilter().settings, MATCH_TUNABLES, 'match.')
        name = manager.name

        def relocalized(found: Relocalization) -> None:
            logger.notice(f'{name}: the scans stopped fitting the map at the filter\'s pose: '
                          f're-localized, {found.describe()}')

        localizer: Method = (LineLocalizer(wall_map, self.tuned.current, on_relocalize=relocalized)
                             if method == 'lines' else ScanLocalizer(wall_points(wall_map.walls)))
        super().__init__(manager, logger, localizer, status=STATUS, laser=laser, start_running=start_running)

    def command(self) -> None:
        """Start the find-wall: -1 while searching (the next good scan)."""
        self.find_wall_pending = True
        self.element[1] = -1
        self.publish_status()

    def on_scan(self, scan: Scan) -> None:
        if not self.find_wall_pending:
            return
        self.find_wall_pending = False
        wall = find_wall(scan.lines())
        if wall is None:
            self.element[1], self.data = 0, []
        else:
            self.element[1], self.data = int(wall.points), wall.parameters()
        self.publish_status()


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('poseModule')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'm:s:xe:').user
    map_file = config_file(manager, opts.get('m'), 'map.xml')
    method = opts.get('e', 'lines')
    try:
        if method not in METHODS:
            raise ConfigError(argv[0], None, f'-e {method}: the methods are {", ".join(METHODS)}')
        data = load_map(map_file)
        if not data.walls:
            raise ConfigError(map_file, None, 'the map has no walls to localize against')
    except ConfigError as error:
        return exit_on_config_error(argv[0], error)
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = PoseModule(manager, logger, WallMap(np.asarray(data.walls, dtype=float)),
                        laser=opts.get('s', 'PlutoLaser'), start_running='x' not in opts, method=method)
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: map {data.name} ({len(data.walls)} walls), method {method}')
    return run_loop(manager, module.step, lambda: None)


if __name__ == '__main__':
    sys.exit(main())
