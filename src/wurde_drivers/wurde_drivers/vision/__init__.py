"""The VisionModule (WURDE guide 7.2): cameras, operators and the ``vision_module`` program.

- :mod:`.camera_config`, :mod:`.vision_config`: the two XML files (guide 7.2.1, 7.2.2);
- :mod:`.camera`: the camera base class (retry on a vanished device) and :class:`.Frame`;
  backends :mod:`.playback`, :mod:`.capture` (``firewire``: an OpenCV capture device) and the
  simulator's ``sim`` camera (``wurde_drivers.sim.dummies.camera``), found by :mod:`.registry`;
- :mod:`.operator`: the operator base class; :mod:`.operators` the shipped ones (guide 7.2.3);
- :mod:`.formats`: pure pixel conversions (gray, rgb, yuv24, yuv422);
- :mod:`.runner`: one loop turn of a layout's cameras and operators; :mod:`.control`: the
  VisionControl stream; :mod:`.module`: the program.
"""

from .camera import Camera, Frame
from .camera_config import CameraSpec, load_camera_config
from .operator import Operator, OperatorContext
from .vision_config import OperatorSpec, load_vision_config

__all__ = ['Camera', 'CameraSpec', 'Frame', 'Operator', 'OperatorContext', 'OperatorSpec',
           'load_camera_config', 'load_vision_config']
