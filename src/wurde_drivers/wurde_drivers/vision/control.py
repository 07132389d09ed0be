"""VisionControl: a running VisionModule's status and commands (its stream ``<module>Control``).

Data (once a second and after each command): the layout, its cameras and their types, its
operators with their types, cameras (comma separated) and whether each runs, the frame rate
over the last second and the frames taken since the start. Requests set ``command``:
1 start and 2 stop operator ``operator_name``; 3 set its option ``option_name`` to
``option_value`` (checked as the config's would be; a bad one is refused and logged);
4 reload: the vision config is read again and the options of this layout's operators are
applied (adding or removing cameras or operators needs a restart, and is logged as such).
"""

from __future__ import annotations

import time
from typing import Any

from wurde_core.interfaces import VisionControl
from wurde_idl.errors import ConfigError

from .runner import VisionModule
from .vision_config import load_vision_config

__all__ = ['START', 'STOP', 'SET_OPTION', 'RELOAD', 'VisionControlSupplier']

START, STOP, SET_OPTION, RELOAD = 1, 2, 3, 4
STATUS_PERIOD_S = 1.0


class VisionControlSupplier:
    """Supplies VisionControl for ``runner``; :meth:`step` once per loop turn."""

    def __init__(self, manager: Any, runner: VisionModule, logger: Any, vision_path: str) -> None:
        self.runner = runner
        self.logger = logger
        self.vision_path = vision_path
        self.stream = VisionControl(f'{manager.name}Control')
        self.stream.set_queue_mode(True)   # every command, in order
        manager.register_supplier(self.stream)
        self._next_status = 0.0

    def step(self) -> None:
        changed = False
        while self.stream.get_next_request():
            request = self.stream.requests
            self._command(request.command.get_value(), request.operator_name.get_value(),
                          request.option_name.get_value(), request.option_value.get_value())
            changed = True
        if changed or time.monotonic() >= self._next_status:
            self._publish()

    def _command(self, command: int, name: str, option: str, value: str) -> None:
        if command == RELOAD:
            self._reload()
            return
        operator = self.runner.operator(name)
        if operator is None:
            self.logger.warn(f'VisionControl: no operator "{name}" (command {command})')
            return
        if command in (START, STOP):
            operator.running = command == START
            self.logger.notice(f'operator {name} {"started" if operator.running else "stopped"}')
        elif command == SET_OPTION:
            try:
                operator.set_option(option, value)
                self.logger.notice(f'operator {name}: {option} = {value}')
            except ConfigError as error:
                self.logger.warn(f'VisionControl: {error}')
        else:
            self.logger.warn(f'VisionControl: unknown command {command}')

    def _reload(self) -> None:
        try:
            layout = load_vision_config(self.vision_path).module(self.runner.layout.name)
        except ConfigError as error:
            self.logger.warn(f'VisionControl reload refused: {error}')
            return
        for spec in layout.operators:
            operator = self.runner.operator(spec.name)
            if operator is None or type(operator).__name__ != spec.type or spec.cameras != operator.cameras:
                self.logger.warn(f'reload: operator {spec.name} is new or changed type or cameras: '
                                 'restart the module to use it')
                continue
            for option, value in {**operator.OPTIONS, **spec.options}.items():
                if operator.options.get(option) != value:
                    try:
                        operator.set_option(option, value)
                    except ConfigError as error:
                        self.logger.warn(f'reload: {error}')
        self.logger.notice(f'reloaded {self.vision_path}')

    def _publish(self) -> None:
        runner, data = self.runner, self.stream.data
        data.layout = runner.layout.name
        data.cameras = [c.name for c in runner.cameras]
        data.camera_types = [c.type_name for c in runner.cameras]
        data.operator_names = [o.name for o in runner.operators]
        data.operator_types = [type(o).__name__ for o in runner.operators]
        data.operator_cameras = [','.join(o.cameras) for o in runner.operators]
        data.operator_running = [o.running for o in runner.operators]
        data.frame_rate = runner.frame_rate
        data.frame_count = runner.frame_count
        if self.stream.publish_data():
            self._next_status = time.monotonic() + STATUS_PERIOD_S
