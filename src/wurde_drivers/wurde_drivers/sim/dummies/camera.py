"""The ``sim`` camera: the simulated robot's eyes, for the VisionModule (WURDE guide 7.2.1's
camera types, plus ours).

It follows the simulator's ground truth (Egomotion ``<base name>Truth``, as the dummy laser
does; option ``truth`` names another stream) and renders what a camera at the robot's pose sees
in the sim config's map (:func:`wurde_drivers.sim.render.render`): walls where the map has them.
Options (in the camera config): ``simConfig`` (default ``sim-config.xml``; relative: the camera
config's directory, else the WURDE config directory), ``truth``, ``width``, ``height``,
``frameRate`` (Hz, default 10), ``fieldOfView`` (degrees, 60), ``cameraHeight`` (1.0 m),
``wallHeight`` (2.0 m), ``maxRange`` (20 m). No frame until the first pose has arrived.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from wurde_core.interfaces import Egomotion
from wurde_idl.errors import ConfigError

from ...errors import DeviceError
from ...vision.camera import Camera
from ...vision.camera_config import CameraSpec
from ..loading import load_sim
from ..render import View, render
from ..world import World

__all__ = ['SimCamera']


class SimCamera(Camera):
    """Renders the simulated map from the robot's true pose; see the module docstring."""

    type_name = 'sim'

    def __init__(self, spec: CameraSpec, report: Callable[[str], object] = print,
                 note: Callable[[str], object] | None = None) -> None:
        super().__init__(spec, report, note)
        self.view = View(width=int(spec.number('width', minimum=2, integer=True)),
                         height=int(spec.number('height', minimum=2, integer=True)),
                         field_of_view=math.radians(spec.number('fieldOfView', minimum=1.0)),
                         camera_height=spec.number('cameraHeight', minimum=0.0),
                         wall_height=spec.number('wallHeight', minimum=0.0),
                         max_range=spec.number('maxRange', minimum=0.1))
        self.sim_config = spec.path_option('simConfig')
        self.truth: Egomotion | None = None
        self.world: World | None = None
        self.pose: tuple[float, float, float] | None = None
        self.distances: NDArray[np.float64] | None = None   # of the last frame, per column
        self._stamp = 0.0                                    # of the pose

    def attach(self, manager: Any) -> None:
        """Read the sim config and map (:raises ConfigError:) and follow the truth stream."""
        path = self.sim_config
        if not os.path.exists(path):
            path = os.path.join(manager.config.get_config_directory(), self.spec.text('simConfig'))
        try:
            config, self.world, _ = load_sim(path)
        except ConfigError as error:
            raise self.spec.error(f'simConfig: {error}') from error
        self.truth = Egomotion(self.spec.text('truth') or config.base.truth_stream)
        manager.register_consumer(self.truth)

    def _open(self) -> None:
        if self.world is None or self.truth is None:
            raise DeviceError('not attached to a module')

    def _grab(self) -> tuple[NDArray[np.uint8], float, int | None] | None:
        assert self.truth is not None and self.world is not None
        while self.truth.get_next_data():
            loc = self.truth.data.location
            self.pose = (loc.x(), loc.y(), loc.theta())
            self._stamp = self.truth.data.timestamp.get_seconds()
        if self.pose is None:
            return None
        image, self.distances = render(self.world, *self.pose, self.view)
        return image, self._stamp, None
