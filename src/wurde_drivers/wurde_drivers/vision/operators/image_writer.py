"""ImageWriter: writes the frames of its camera to disk (WURDE guide 7.2.3).

Options: ``imageDir`` (default: the WURDE data directory), ``imagePrefix`` (default: the
operator's name); ours: ``imageDevice`` (default ``main``) and ``imageSuffix`` (default ``.ppm``,
the guide's; any type OpenCV writes). Each frame goes to
``imagePrefix-[frame index]-imageDevice-[timestamp].imageSuffix``, the name the playback camera
reads, so a written set plays back as it was taken. Any resolution (the guide's was 320x240
only); the guide's 25 fps at 320x240 colour is kept with room to spare (``bench/vision.py``).
Each file appears whole (written under a hidden name, then renamed), so a playback camera
or a viewer reading the directory never sees half a frame. A frame that cannot be written (disk
full, directory removed) is counted and reported once.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from ..camera import Frame
from ..operator import Operator, OperatorContext
from ..vision_config import OperatorSpec
from ..playback import image_name
from .files import output_place, write_image

__all__ = ['ImageWriter']


class ImageWriter(Operator):
    OPTIONS = {'imageDir': '', 'imagePrefix': '', 'imageDevice': 'main', 'imageSuffix': '.ppm'}

    def __init__(self, spec: OperatorSpec) -> None:
        super().__init__(spec)
        self.directory = ''
        self.prefix = ''
        self.written = 0
        self.failed = 0

    def setup(self, context: OperatorContext) -> None:
        super().setup(context)
        self.configure()

    def configure(self) -> None:
        self.directory, self.prefix = output_place(self)

    def path_of(self, frame: Frame) -> str:
        name = image_name(self.prefix, frame.index, self.options['imageDevice'], frame.stamp,
                          self.options['imageSuffix'])
        return os.path.join(self.directory, name)

    def process(self, frames: Mapping[str, Frame]) -> None:
        frame = self.main(frames)
        path = self.path_of(frame)
        if write_image(path, frame.image):
            self.written += 1
            return
        self.failed += 1
        if self.failed == 1:
            self.context.logger.warn(f'{self.name}: cannot write {path}; frames are lost until it can')
