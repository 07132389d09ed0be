"""The VisionModule's work: its layout's cameras and operators, one loop turn at a time.

Built from the two configs (guide 7.2.1, 7.2.2): each camera of the layout from the camera config
(:mod:`.registry` picks the class by type), each operator from its ``<operator>``. A turn reads
every camera (:meth:`Camera.read` never blocks and never raises for a device fault) and gives
each running operator whose first camera has a new frame the newest frame of each of its
cameras. An operator that raises is stopped and reported, not the module.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

from wurde_idl.errors import ConfigError

from .camera import Camera, Frame
from .camera_config import load_camera_config
from .operator import Operator, OperatorContext
from .registry import camera_class, load_plugins, operator_class
from .vision_config import ModuleLayout, load_vision_config

__all__ = ['VisionModule', 'VisionRunner', 'load_layout']


def load_layout(camera_path: str, vision_path: str, name: str, report: Callable[[str], object],
                note: Callable[[str], object] | None = None
                ) -> tuple[ModuleLayout, list[Camera], list[Operator]]:
    """Read both configs and build the cameras and operators of layout ``name`` (no I/O yet);
    ``report`` and ``note`` are the cameras' (:class:`Camera`).

    :raises ConfigError: either file is bad, there is no layout ``name``, it names a camera the
        camera config lacks, an operator type is unknown or its options are bad.
    """
    cameras = load_camera_config(camera_path)
    vision = load_vision_config(vision_path)
    layout = vision.module(name)
    for camera in layout.cameras:
        if camera not in cameras:
            raise ConfigError(layout.path, layout.line, f'module "{name}" opens camera "{camera}", '
                              f'which {camera_path} does not define (cameras: {", ".join(cameras)})')
    plugins = load_plugins(vision.plugins, note or report)
    built = [camera_class(cameras[c].type)(cameras[c], report, note) for c in layout.cameras]
    operators = [operator_class(spec, plugins)(spec) for spec in layout.operators]
    return layout, built, operators


class VisionModule:
    """Cameras and operators of one layout; :meth:`step` once per loop turn."""

    def __init__(self, layout: ModuleLayout, cameras: list[Camera], operators: list[Operator],
                 logger: Any) -> None:
        self.layout = layout
        self.cameras = cameras
        self.operators = operators
        self.logger = logger
        self.latest: dict[str, Frame] = {}
        self.frame_count = 0
        self._rate_start = time.monotonic()
        self._rate_frames = 0
        self.frame_rate = 0.0

    def setup(self, manager: Any) -> None:
        """Attach the cameras and set up the operators. :raises ConfigError:"""
        for camera in self.cameras:
            camera.attach(manager)
        context = OperatorContext(manager, self.logger, manager.config.get_data_directory())
        for operator in self.operators:
            operator.setup(context)

    def operator(self, name: str) -> Operator | None:
        return next((o for o in self.operators if o.name == name), None)

    def step(self) -> None:
        new: set[str] = set()
        for camera in self.cameras:
            frame = camera.read()
            if frame is not None:
                self.latest[camera.name] = frame
                new.add(camera.name)
                self.frame_count += 1
                self._rate_frames += 1
        now = time.monotonic()
        if now - self._rate_start >= 1.0:
            self.frame_rate = self._rate_frames / (now - self._rate_start)
            self._rate_start, self._rate_frames = now, 0
        for operator in self.operators:
            if not operator.running or operator.cameras[0] not in new:
                continue
            frames = {c: self.latest[c] for c in operator.cameras if c in self.latest}
            try:
                operator.process(frames)
                operator.processed += 1
            except Exception as error:  # an operator's bug must not end the module
                operator.running = False
                self.logger.error(f'operator {operator.name} stopped: {error!r}')

    def wait_s(self) -> float:
        """Until the next frame of any camera is due."""
        return min((camera.wait_s() for camera in self.cameras), default=math.inf)

    def close(self) -> None:
        """Shut the operators down and close the cameras; idempotent."""
        for operator in self.operators:
            try:
                operator.shutdown()
            except Exception as error:
                self.logger.error(f'operator {operator.name} shutdown: {error!r}')
        for camera in self.cameras:
            camera.close()


VisionRunner = VisionModule  # old name (docs/naming.md)
