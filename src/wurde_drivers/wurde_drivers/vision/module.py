"""vision_module: the VisionModule (WURDE guide 7.2), a single binary that runs operators on
cameras as its configuration says.

Options (guide 7.2): ``-c FILE`` the camera config (default ``camera-config.xml`` in the config
directory, :mod:`.camera_config`), ``-v FILE`` the vision config (default ``vision-config.xml``,
:mod:`.vision_config`), ``-n NAME`` the module's name, which also picks the ``<module>`` layout
of the vision config. A bad config (either file, an unknown layout, camera, operator type or
option) ends the program with status 2 and ``file:line: reason``. A camera that is absent or
vanishes is reported and retried (:mod:`.camera`); the module also supplies VisionControl on
``<NAME>Control`` (:mod:`.control`).
"""

from __future__ import annotations

import sys

from wurde_core import CommsManager, Logger
from wurde_idl.errors import ConfigError

from ..module_setup import config_file, exit_on_config_error, run_loop, set_loop
from .control import VisionControlSupplier
from .runner import VisionModule, load_layout

#: Longest sleep of a loop turn (s); shorter when a camera's next frame is due sooner.
LOOP_S = 0.01


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('VisionModule')
    manager.set_help_string('  -c FILE  camera-config.xml (default: <config dir>/camera-config.xml)\n'
                            '  -v FILE  vision-config.xml (default: <config dir>/vision-config.xml)\n'
                            '  -n NAME  the module name; picks the <module> of the vision config')
    opts = manager.parse_options(argv, 'c:v:')
    camera_path = config_file(manager, opts.user.get('c'), 'camera-config.xml')
    vision_path = config_file(manager, opts.user.get('v'), 'vision-config.xml')
    logger = Logger(manager.name)
    try:
        layout, cameras, operators = load_layout(camera_path, vision_path, manager.name, logger.warn,
                                                   logger.notice)
        manager.register_supplier(logger)
        runner = VisionModule(layout, cameras, operators, logger)
        runner.setup(manager)
    except ConfigError as error:
        manager.clean_up()
        return exit_on_config_error(argv[0], error)
    control = VisionControlSupplier(manager, runner, logger, vision_path)
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: cameras {", ".join(c.name for c in cameras)}; operators '
                  f'{", ".join(f"{o.name} ({type(o).__name__})" for o in operators)}')

    def step() -> None:
        runner.step()
        control.step()
        manager.set_sleep_only(min(LOOP_S, runner.wait_s()))

    return run_loop(manager, step, runner.close)


if __name__ == '__main__':
    sys.exit(main())
