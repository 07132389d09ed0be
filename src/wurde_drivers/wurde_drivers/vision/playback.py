"""The ``playback`` camera: logged images played back as a camera (WURDE guide 7.2.1).

Options: ``imageDirectory`` (required; relative: from the camera config's directory),
``imageSuffix`` (default ``.ppm``; any image type OpenCV reads), ``imagePrefix``,
``imageDevice`` ("main" or "stereo" for the StereoDataCollector's logs), and ours:
``frameRate`` (Hz, default 10; 0 = one frame per loop turn) and ``loop`` (start again at the end).

File names are, as the guide gives them,
``imagePrefix-[integer frame number]-imageDevice-[floating point timestamp in seconds].imageSuffix``
(an empty prefix or device drops its part and its dash). Files are played in frame-number order
(numeric, so 10 follows 9), each frame keeping its logged index and timestamp; other files are
ignored. A file OpenCV cannot read (corrupt, truncated, not an image) is skipped, counted in
:attr:`PlaybackCamera.skipped` and reported by name — never a crash. A directory that is absent
or holds no matching image is an absent device: reported and retried.
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Callable
from typing import cast

import cv2
import numpy as np
from numpy.typing import NDArray

from ..errors import DeviceError
from .camera import Camera
from .camera_config import CameraSpec

__all__ = ['PlaybackCamera', 'image_name', 'image_pattern', 'list_images']

_FLOAT = r'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?'


def image_name(prefix: str, index: int, device: str, stamp: float, suffix: str) -> str:
    """The guide's file name of frame ``index`` taken at ``stamp`` (also what the writers use)."""
    parts = [part for part in (prefix, str(index), device, f'{stamp:.6f}') if part]
    return '-'.join(parts) + suffix


def image_pattern(prefix: str, device: str, suffix: str) -> re.Pattern[str]:
    """A regular expression matching :func:`image_name`'s names; groups: index, stamp."""
    head = re.escape(prefix) + '-' if prefix else ''
    middle = '-' + re.escape(device) if device else ''
    return re.compile(f'^{head}(\\d+){middle}-({_FLOAT}){re.escape(suffix)}$')


def list_images(directory: str, prefix: str, device: str, suffix: str) -> list[tuple[int, float, str]]:
    """``(frame index, stamp, path)`` of every matching file, in frame order.

    :raises OSError: the directory cannot be listed.
    """
    pattern = image_pattern(prefix, device, suffix)
    found = []
    for entry in os.listdir(directory):
        match = pattern.match(entry)
        if match:
            found.append((int(match.group(1)), float(match.group(2)), os.path.join(directory, entry)))
    return sorted(found)


class PlaybackCamera(Camera):
    """Plays the images of a directory; see the module docstring."""

    type_name = 'playback'

    def __init__(self, spec: CameraSpec, report: Callable[[str], object] = print,
                 note: Callable[[str], object] | None = None) -> None:
        super().__init__(spec, report, note)
        self.directory = spec.path_option('imageDirectory')
        self.prefix, self.device = spec.text('imagePrefix'), spec.text('imageDevice')
        self.suffix = spec.text('imageSuffix')
        self.loop = spec.flag('loop')
        self.skipped = 0        # unreadable files (each time one is met)
        self._named: set[str] = set()   # unreadable files already reported
        self.finished = False   # every image played (and not looping)
        self._files: list[tuple[int, float, str]] = []
        self._next = 0

    def _open(self) -> None:
        try:
            self._files = list_images(self.directory, self.prefix, self.device, self.suffix)
        except OSError as error:
            raise DeviceError(f'image directory {self.directory}: {error.strerror}') from error
        if not self._files:
            example = image_name(self.prefix, 0, self.device, 0.0, self.suffix)
            raise DeviceError(f'no images named like {example} in {self.directory}')
        self._next = 0

    def _grab(self) -> tuple[NDArray[np.uint8], float, int | None] | None:
        bad = 0
        while True:
            if self._next >= len(self._files):
                if not self.loop:
                    if not self.finished:
                        self.finished = True
                        self.note(f'camera {self.name}: played all {len(self._files)} images '
                                    f'of {self.directory} ({self.skipped} skipped)')
                    return None
                self._next = 0
            index, stamp, path = self._files[self._next]
            self._next += 1
            try:
                image = cv2.imread(path, cv2.IMREAD_COLOR)
            except cv2.error:
                image = None      # OpenCV refused it loudly rather than returning nothing
            if image is not None:
                return cast(NDArray[np.uint8], image), stamp if stamp > 0 else time.time(), index
            self.skipped += 1
            bad += 1
            if path not in self._named:       # once per file, not once per pass of a loop
                self._named.add(path)
                self.report(f'camera {self.name}: skipped {path}: not an image OpenCV can read')
            if bad >= len(self._files):
                raise DeviceError(f'no readable image in {self.directory}')
