"""The ``firewire`` camera as an OpenCV capture device (WURDE guide 7.2.1).

WURDE drove IEEE 1394 cameras through libdc1394; here the type keeps its name and its options but
opens whatever ``cv2.VideoCapture`` opens: ``id`` is a device index (``0``), a device path
(``/dev/video0``), a video file or a stream URL. A 64-bit IEEE 1394 id, as the guide's example
gives, names no OpenCV device: it is reported absent (and retried, in case it is a real index).

The guide's picture options map to ``CAP_PROP_*`` (:data:`PROPERTIES`); ``shutter`` and
``autoiris`` have no OpenCV property, and a property the device refuses is not applied: each is
reported once, naming the option. Ours: ``width``, ``height`` (any resolution the device
gives), ``frameRate``. A device that is absent, fails to open or stops giving frames (unplugged;
a video file at its end) is closed, reported and opened again every second
(:class:`~wurde_drivers.vision.camera.Camera`) — never a crash.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import cast

import cv2
import numpy as np
from numpy.typing import NDArray

from ..errors import DeviceError
from .camera import Camera
from .camera_config import CameraSpec

__all__ = ['PROPERTIES', 'CaptureCamera', 'device_of']

#: Guide option -> OpenCV property (None: OpenCV has none).
PROPERTIES: dict[str, int | None] = {
    'brightness': cv2.CAP_PROP_BRIGHTNESS, 'exposure': cv2.CAP_PROP_EXPOSURE,
    'sharpness': cv2.CAP_PROP_SHARPNESS, 'hue': cv2.CAP_PROP_HUE,
    'saturation': cv2.CAP_PROP_SATURATION, 'gamma': cv2.CAP_PROP_GAMMA, 'shutter': None,
    'gain': cv2.CAP_PROP_GAIN, 'iris': cv2.CAP_PROP_IRIS, 'focus': cv2.CAP_PROP_FOCUS,
    'zoom': cv2.CAP_PROP_ZOOM, 'autoiris': None,
    'width': cv2.CAP_PROP_FRAME_WIDTH, 'height': cv2.CAP_PROP_FRAME_HEIGHT,
}
#: Largest number taken as a device index; a larger one is a 1394 id.
_MAX_INDEX = 1023


def device_of(camera_id: str) -> int | str:
    """What ``cv2.VideoCapture`` is given for ``id``: an index, or the text (a path or URL)."""
    try:
        return int(camera_id, 0)
    except ValueError:
        return camera_id


class CaptureCamera(Camera):
    """A ``cv2.VideoCapture`` device; see the module docstring."""

    type_name = 'firewire'

    def __init__(self, spec: CameraSpec, report: Callable[[str], object] = print,
                 note: Callable[[str], object] | None = None) -> None:
        super().__init__(spec, report, note)
        self.device = device_of(spec.text('id'))
        self.settings: dict[str, float] = {}
        for name, prop in PROPERTIES.items():
            raw = spec.text(name)
            if not raw:
                continue
            if prop is None:
                report(f'camera {self.name}: option {name} has no OpenCV capture property; ignored')
            else:
                self.settings[name] = spec.number(name)
        self._capture: cv2.VideoCapture | None = None
        self._warned: set[str] = set()

    def _open(self) -> None:
        device = self.device
        if isinstance(device, int) and not 0 <= device <= _MAX_INDEX:
            raise DeviceError(f'id {self.spec.text("id")} names no capture device (an IEEE 1394 id? '
                              'give a device index, a /dev/video path or a video file)')
        if isinstance(device, str) and '://' not in device and not os.path.exists(device):
            raise DeviceError(f'{device}: no such device or file')
        try:
            capture = cv2.VideoCapture(device)
        except cv2.error as error:
            raise DeviceError(f'OpenCV cannot open {device}: {error}') from error
        if not capture.isOpened():
            capture.release()
            raise DeviceError(f'OpenCV cannot open {device}')
        for name, value in self.settings.items():
            prop = PROPERTIES[name]
            assert prop is not None
            if not capture.set(prop, value) and name not in self._warned:
                self._warned.add(name)
                self.report(f'camera {self.name}: the device refused option {name}={value:g}')
        self._capture = capture

    def _grab(self) -> tuple[NDArray[np.uint8], float, int | None] | None:
        assert self._capture is not None
        try:
            ok, image = self._capture.read()
        except cv2.error as error:
            raise DeviceError(f'{self.device}: {error}') from error
        if not ok or image is None:
            raise DeviceError(f'{self.device} gave no frame (unplugged, or the end of a file)')
        if image.ndim == 2:
            image = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
        return cast(NDArray[np.uint8], image), time.time(), None

    def _close(self) -> None:
        if self._capture is not None:
            self._capture.release()
            self._capture = None
